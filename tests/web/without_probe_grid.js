#!/usr/bin/env node
// without_probe_grid.js IN.glb OUT.glb: IN with scene.extensions.LIGHTBAKE_light_probes taken
// out (the rest byte for byte), so a reader lights its moving objects from the nodes' centre
// blends alone (extras.lightbake_probe_sh): the three.js check's control for the per-vertex
// blends (run_threejs_check.sh). Exits 2 on a file that is not a .glb with the grid.
const fs = require('fs');

function main([input, output]) {
  const bytes = fs.readFileSync(input);
  if (bytes.readUInt32LE(0) !== 0x46546c67) throw new Error(`${input}: not a .glb`);
  const length = bytes.readUInt32LE(12);
  const json = JSON.parse(bytes.subarray(20, 20 + length).toString('utf8'));
  const scene = json.scenes[json.scene || 0];
  if (!scene.extensions || !scene.extensions.LIGHTBAKE_light_probes)
    throw new Error(`${input}: no LIGHTBAKE_light_probes`);
  delete scene.extensions.LIGHTBAKE_light_probes;
  let text = Buffer.from(JSON.stringify(json), 'utf8');
  text = Buffer.concat([text, Buffer.alloc((4 - (text.length % 4)) % 4, 0x20)]);
  const rest = bytes.subarray(20 + length);
  const header = Buffer.alloc(20);
  header.write('glTF', 0, 'latin1');
  header.writeUInt32LE(2, 4);
  header.writeUInt32LE(20 + text.length + rest.length, 8);
  header.writeUInt32LE(text.length, 12);
  header.write('JSON', 16, 'latin1');
  fs.writeFileSync(output, Buffer.concat([header, text, rest]));
}

try {
  main(process.argv.slice(2));
} catch (error) {
  console.error(error.message);
  process.exit(2);
}
