#!/usr/bin/env node
// check_probe_blends.js BLENDS.json FILE.glb MOVED.glb MAX_RELATIVE [--dark-over-lit MAX]
//                       [--expect-ring NAME:R]
// The three.js check's probe blends (threejs_screenshot.js writes BLENDS.json: probe_grid.js's
// blend of FILE.glb's grid at each moving object's centre, `file`, and at the one it moved,
// `moved`) against the C++ blend of the same grid at the same points, which the exports wrote
// as the nodes' extras.lightbake_probe_sh: FILE.glb's where its objects stand, MOVED.glb's (the
// same scene with the moved object elsewhere) at the moved one. Two implementations of one rule
// (docs/light-probes.md), so they agree to float rounding: the largest difference over the 27
// numbers, over the largest of the C++ numbers, must be at most MAX_RELATIVE.
// --dark-over-lit MAX: the moved place is behind a wall from the light, the file's place in
// front of it; the mean irradiance over the object's normals (pi Y_00 c_00, mean over RGB)
// behind must be below MAX times that in front, in three.js and in the exports, and the blend
// without visibility rays (the control) must exceed it there, so the check can fail.
// --expect-ring NAME:R: the JavaScript blend of object NAME where the file put it used ring R
// (1: its 8 probes all refused, the 4 x 4 x 4 block's outer probes blended).
// Not vacuous: the exports' blends at the two places of the move must differ by more than 100
// times MAX_RELATIVE. Exits 1 when a check fails, 2 on bad input.
const fs = require('fs');

function glbJson(file) {
  const bytes = fs.readFileSync(file);
  if (bytes.readUInt32LE(0) !== 0x46546c67) return JSON.parse(bytes.toString('utf8'));  // .gltf
  const length = bytes.readUInt32LE(12);
  return JSON.parse(bytes.subarray(20, 20 + length).toString('utf8'));
}

function exportedBlend(file, name) {
  const node = glbJson(file).nodes.find((n) => n.name === name && n.extras && n.extras.dynamic);
  if (!node || !Array.isArray(node.extras.lightbake_probe_sh))
    throw new Error(`${file}: no moving node '${name}' with extras.lightbake_probe_sh`);
  return node.extras.lightbake_probe_sh;
}

function relativeDifference(js, cpp) {
  let difference = 0, largest = 0;
  cpp.forEach((c, k) => {
    difference = Math.max(difference, Math.abs(js[k] - c));
    largest = Math.max(largest, Math.abs(c));
  });
  return largest > 0 ? difference / largest : difference;
}

const meanIrradiance = (sh) => Math.PI * 0.282095 * (sh[0] + sh[1] + sh[2]) / 3;  // W/m^2

function parseArguments(argv) {
  const usage = 'usage: check_probe_blends.js BLENDS.json FILE.glb MOVED.glb MAX_RELATIVE ' +
                '[--dark-over-lit MAX] [--expect-ring NAME:R]';
  if (argv.length < 4) throw new Error(usage);
  const options = { blends: argv[0], file: argv[1], moved: argv[2], maxRelative: Number(argv[3]),
                    darkOverLit: null, expectRing: null };
  for (let i = 4; i < argv.length; i += 2) {
    if (argv[i] === '--dark-over-lit' && i + 1 < argv.length) {
      options.darkOverLit = Number(argv[i + 1]);
    } else if (argv[i] === '--expect-ring' && i + 1 < argv.length) {
      const [name, ring] = argv[i + 1].split(':');
      options.expectRing = { name, ring: Number(ring) };
    } else {
      throw new Error(usage);
    }
  }
  return options;
}

function main(argv) {
  const options = parseArguments(argv);
  const blends = JSON.parse(fs.readFileSync(options.blends, 'utf8')).blends;
  const moved = blends.find((b) => b.place === 'moved');
  if (!moved) throw new Error(`${options.blends}: no moved object`);
  const here = blends.find((b) => b.place === 'file' && b.name === moved.name);
  let status = 0;
  for (const blend of blends) {
    const file = blend.place === 'moved' ? options.moved : options.file;
    const cpp = exportedBlend(file, blend.name);
    const relative = relativeDifference(blend.sh, cpp);
    const point = blend.at.map((v) => v.toFixed(4)).join(', ');
    console.log(`probe blend of ${blend.name} at (${point}), ${blend.place}: three.js ` +
                `${blend.probes} probes (ring ${blend.ring}), mean E ` +
                `${meanIrradiance(blend.sh).toPrecision(5)} W/m^2; C++ ` +
                `(${file.split('/').pop()}) ${meanIrradiance(cpp).toPrecision(5)}; largest ` +
                `difference ${relative.toExponential(2)} of the largest coefficient ` +
                `(limit ${options.maxRelative})`);
    if (!(relative <= options.maxRelative)) {
      console.log(`  three.js's blend differs from the C++ blend beyond ${options.maxRelative}`);
      status = 1;
    }
  }
  const expect = options.expectRing;
  if (expect) {
    const blend = blends.find((b) => b.place === 'file' && b.name === expect.name);
    if (!blend || blend.ring !== expect.ring) {
      console.log(`${expect.name}: three.js blended ring ${blend ? blend.ring : 'none'}, ` +
                  `not ring ${expect.ring}: the check does not exercise it`);
      status = 1;
    }
  }
  // Not vacuous: the light where the object stood must differ from where it went, or a blend
  // left unchanged by the move would pass.
  const cppHere = exportedBlend(options.file, moved.name);
  const cppMoved = exportedBlend(options.moved, moved.name);
  const moveChange = Math.min(relativeDifference(cppHere, cppMoved),
                              relativeDifference(cppMoved, cppHere));
  console.log(`the exports' blends at the two places differ by ${moveChange.toExponential(2)}`);
  if (!(moveChange > 100 * options.maxRelative)) {
    console.log('  the two places get alike light: the check cannot tell a blend left unmoved');
    status = 1;
  }
  if (options.darkOverLit !== null) {
    const max = options.darkOverLit;
    const lit = meanIrradiance(here.sh);
    const ratios = {
      'three.js': meanIrradiance(moved.sh) / lit,
      exports: meanIrradiance(cppMoved) / meanIrradiance(cppHere),
      'three.js without visibility rays (the control)': meanIrradiance(moved.unoccluded) / lit,
    };
    for (const [who, ratio] of Object.entries(ratios)) {
      const control = who.includes('control');
      console.log(`behind the wall / in front, ${who}: ${(100 * ratio).toFixed(3)}% ` +
                  `(${control ? 'must exceed' : 'limit'} ${100 * max}%)`);
      if (control ? !(ratio > max) : !(ratio < max)) {
        console.log(control ? '  the control is within the limit too: the check cannot fail'
                            : '  light leaks through the wall');
        status = 1;
      }
    }
  }
  return status;
}

try {
  process.exit(main(process.argv.slice(2)));
} catch (error) {
  console.error(`check_probe_blends: ${error.message}`);
  process.exit(2);
}
