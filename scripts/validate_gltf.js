#!/usr/bin/env node
// Runs the Khronos glTF-Validator (npm `gltf-validator`) on one .glb/.gltf and prints its
// counts and messages; exit status 1 when it reports errors or warnings.
// Install: npm install --prefix build/npm gltf-validator
// Run:     NODE_PATH=build/npm/node_modules node scripts/validate_gltf.js out.glb
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');

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
    for (const m of i.messages) console.log(`  [${m.severity}] ${m.code} ${m.pointer || ''}: ${m.message}`);
    process.exit(i.numErrors + i.numWarnings > 0 ? 1 : 0);
  })
  .catch((error) => {
    console.error(`${file}: validator failed: ${error}`);
    process.exit(2);
  });
