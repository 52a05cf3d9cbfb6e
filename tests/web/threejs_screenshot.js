#!/usr/bin/env node
// Renders lightbake exports with three.js in headless Chromium and saves each frame as PNG.
//   NODE_PATH=build/npm/node_modules node tests/web/threejs_screenshot.js \
//     --three build/npm/node_modules/three --size 256x192 [--chromium /usr/bin/chromium] \
//     [--exposure STOPS] [--groups W1,W2,...] [--move NAME:X,Y,Z] scene.glb out.png [... ]
// --exposure applies to the files after it (default: the camera's lightbake_exposure_stops);
// --groups to the next file alone: its light groups' weights (LIGHTBAKE_lightmap_groups);
// --move to the next file alone: its moving object NAME's new centre (the file's frame), lit
// from the file's probe grid there. The probe-lit objects' blends (probe_grid.js) are written
// beside each frame that has any, OUT.png -> OUT_probes.json.
// Starts its own HTTP server on 127.0.0.1 (a free port chosen by the system) serving this
// folder (the page), three's package and the folders of the given files, and stops it at the
// end. Exit status 1 on any page error.
const fs = require('fs');
const http = require('http');
const path = require('path');
const puppeteer = require('puppeteer-core');

function parseArguments(argv) {
  const options = { chromium: '/usr/bin/chromium', size: '256x192', three: '', pairs: [] };
  const rest = [];
  let exposure = null;
  let groups = null;
  let move = null;
  for (let i = 0; i < argv.length; ++i) {
    if (argv[i] === '--chromium') options.chromium = argv[++i];
    else if (argv[i] === '--size') options.size = argv[++i];
    else if (argv[i] === '--three') options.three = argv[++i];
    else if (argv[i] === '--exposure') exposure = Number(argv[++i]);
    else if (argv[i] === '--groups') groups = argv[++i];
    else if (argv[i] === '--move') move = argv[++i];
    else {
      rest.push([argv[i], exposure, groups, move]);
      if (rest.length % 2 === 0) groups = move = null;
    }
  }
  if (!options.three || rest.length === 0 || rest.length % 2 !== 0) {
    console.error('usage: threejs_screenshot.js --three DIR [--size WxH] [--chromium PATH] ' +
                  '[--exposure STOPS] IN.glb OUT.png [[--exposure STOPS] IN.glb OUT.png ...]');
    process.exit(2);
  }
  for (let i = 0; i < rest.length; i += 2)
    options.pairs.push([path.resolve(rest[i][0]), rest[i + 1][0], ...rest[i].slice(1)]);
  const [width, height] = options.size.split('x').map(Number);
  options.width = width;
  options.height = height;
  return options;
}

const contentTypes = {
  '.html': 'text/html', '.js': 'text/javascript', '.json': 'application/json',
  '.glb': 'model/gltf-binary', '.gltf': 'model/gltf+json', '.png': 'image/png',
  '.bin': 'application/octet-stream', '.wasm': 'application/wasm',
};

// URL prefixes -> folders; nothing outside them is served.
function startServer(roots) {
  const server = http.createServer((request, response) => {
    const url = decodeURIComponent(new URL(request.url, 'http://localhost').pathname);
    for (const [prefix, folder] of Object.entries(roots)) {
      if (!url.startsWith(prefix)) continue;
      const file = path.join(folder, url.slice(prefix.length));
      if (!file.startsWith(folder + path.sep) || !fs.existsSync(file) ||
          !fs.statSync(file).isFile()) break;
      response.writeHead(200, {
        'Content-Type': contentTypes[path.extname(file)] || 'application/octet-stream',
        'Cache-Control': 'no-store',
      });
      fs.createReadStream(file).pipe(response);
      return;
    }
    response.writeHead(404);
    response.end();
  });
  return new Promise((resolve) => server.listen(0, '127.0.0.1', () => resolve(server)));
}

async function main() {
  const options = parseArguments(process.argv.slice(2));
  const roots = { '/page/': __dirname, '/three/': path.resolve(options.three) };
  const folders = [...new Set(options.pairs.map(([input]) => path.dirname(input)))];
  folders.forEach((folder, i) => { roots[`/files${i}/`] = folder; });
  const server = await startServer(roots);
  const port = server.address().port;
  // SwiftShader (CPU) behind ANGLE: the same pixels on every machine, no GPU needed.
  const browser = await puppeteer.launch({
    executablePath: options.chromium,
    headless: true,
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
           '--disable-dev-shm-usage', '--force-color-profile=srgb'],
  });
  let status = 0;
  try {
    for (const [input, output, exposure, groups, move] of options.pairs) {
      const page = await browser.newPage();
      await page.setViewport({ width: options.width, height: options.height });
      const messages = [];
      page.on('console', (m) => messages.push(`${m.type()}: ${m.text()}`));
      page.on('pageerror', (e) => messages.push(`pageerror: ${e.message}`));
      const folder = folders.indexOf(path.dirname(input));
      const url = `http://127.0.0.1:${port}/page/index.html?file=` +
                  encodeURIComponent(`/files${folder}/${path.basename(input)}`) +
                  `&width=${options.width}&height=${options.height}` +
                  (exposure === null ? '' : `&exposure=${exposure}`) +
                  (groups === null ? '' : `&groups=${groups}`) +
                  (move === null ? '' : `&move=${move}`);
      await page.goto(url);
      await page.waitForFunction('window.lightbakeDone || window.lightbakeError',
                                 { timeout: 30000 });
      const result = await page.evaluate(() => ({
        done: window.lightbakeDone, error: window.lightbakeError,
        png: window.lightbakeDone ? document.querySelector('canvas').toDataURL('image/png') : '',
      }));
      if (result.error) {
        console.error(`${input}: page error: ${result.error}`);
        messages.forEach((m) => console.error(`  ${m}`));
        status = 1;
      } else {
        fs.writeFileSync(output, Buffer.from(result.png.split(',')[1], 'base64'));
        const d = result.done;
        console.log(`${output}: three.js r${d.revision}, ${d.lightmapped} meshes with MOZ_lightmap, ` +
                    `${d.colorPatched} COLOR_0 materials, ${d.rgbmPatched} RGBM materials, ` +
                    `${d.ktx2} maps from KTX2 (${d.ktx2Mipmapped} of them through ` +
                    `${d.ktx2Levels} mip levels, mip-filtered), ` +
                    `${d.groupsPatched} light-group materials, ` +
                    `${d.probeLit} probe-lit meshes` +
                    (d.probeGrid ? ' from the probe grid' : '') + ', ' +
                    `exposure ${d.exposure} stops`);
        if (d.probeBlends.length > 0)
          fs.writeFileSync(output.replace(/\.png$/, '_probes.json'),
                           JSON.stringify({ blends: d.probeBlends }, null, 1) + '\n');
        messages.filter((m) => !m.startsWith('log:')).forEach((m) => console.log(`  ${m}`));
      }
      await page.close();
    }
  } finally {
    await browser.close();
    server.close();
  }
  process.exit(status);
}

main().catch((error) => {
  console.error(`threejs_screenshot: ${error.stack || error}`);
  process.exit(1);
});
