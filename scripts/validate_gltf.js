#!/usr/bin/env node
// Runs the Khronos glTF-Validator (npm `gltf-validator`) on one .glb/.gltf and prints its
// counts and messages; exit status 1 when it reports errors or warnings.
// Install: npm install --prefix build/npm gltf-validator
// Run:     NODE_PATH=build/npm/node_modules node scripts/validate_gltf.js out.glb
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');

// The indices of the images stored as KTX2 (mimeType image/ktx2) in a .glb or .gltf.
function ktx2ImageIndices(file) {
  const bytes = fs.readFileSync(file);
  const json = file.endsWith('.glb')
    ? JSON.parse(bytes.subarray(20, 20 + bytes.readUInt32LE(12)).toString('utf8'))
    : JSON.parse(bytes.toString('utf8'));
  return (json.images || []).flatMap((image, k) => (image.mimeType === 'image/ktx2' ? [k] : []));
}

const file = process.argv[2];
if (!file) {
  console.error('usage: validate_gltf.js FILE.glb|FILE.gltf');
  process.exit(2);
}
validator
  .validateBytes(new Uint8Array(fs.readFileSync(file)), {
    uri: path.basename(file),
    maxIssues: 100,
    externalResourceFunction: (uri) =>
      Promise.resolve(new Uint8Array(fs.readFileSync(path.join(path.dirname(file), uri)))),
  })
  .then((report) => {
    const i = report.issues;
    console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ` +
                `${i.numHints} hints`);
    // This validator predates KHR_texture_basisu: on a KTX2 image (and only there) it warns
    // that the MIME type is not PNG/JPEG and that it cannot read the image. Those two are
    // expected; any other error or warning fails.
    const ktx2Images = new Set(ktx2ImageIndices(file));
    const expected = (m) => ['VALUE_NOT_IN_LIST', 'IMAGE_UNRECOGNIZED_FORMAT'].includes(m.code) &&
      ktx2Images.has(Number((/^\/images\/(\d+)/.exec(m.pointer || '') || [])[1]));
    let failures = 0;
    for (const m of i.messages) {
      const note = m.severity <= 1 && expected(m) ? ' (expected: KTX2, which this validator cannot read)' : '';
      if (m.severity <= 1 && !note) ++failures;
      console.log(`  [${m.severity}] ${m.code} ${m.pointer || ''}: ${m.message}${note}`);
    }
    process.exit(failures > 0 ? 1 : 0);
  })
  .catch((error) => {
    console.error(`${file}: validator failed: ${error}`);
    process.exit(2);
  });
