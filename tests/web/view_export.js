// The page's script (index.html): loads the glTF, applies lightbake's light, draws one frame.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { KTX2Loader } from 'three/addons/loaders/KTX2Loader.js';
import {
  MozLightmapPlugin, addVertexRadiosityAsIrradiance, applyDirectionalLightmaps,
  applyLightGroups, applyProbeLight, decodeRgbmLightmaps, updateProbeLight,
} from './moz_lightmap.js';
import { loadProbeGrid, objectCentre } from './probe_grid.js';

// The probe-lit objects' blends where the file put them, and with the query's `move=NAME:x,y,z`
// the file's moving object NAME moved so that its centre is at that point (the file's frame)
// and lit again from the grid there, as a game would (updateProbeLight). Each blend is reported
// with the same blend without visibility rays (`unoccluded`), the control of the check's wall.
function moveAndReport(gltf, grid, query) {
  const movers = [];
  gltf.scene.traverse((o) => { if (o.isMesh && o.userData.lightbakeProbeSh) movers.push(o); });
  const report = (object, place) => {
    const centre = objectCentre(object);
    const at = grid.frame.worldToLocal(centre.clone()).toArray();
    return { name: object.name, place, at, ...grid.blend(centre),
             unoccluded: grid.blend(centre, { occlusion: false }).sh };
  };
  const blends = movers.map((o) => report(o, 'file'));
  if (query.has('move')) {
    const [name, place] = query.get('move').split(':');
    const object = movers.find((o) => o.name === name);
    if (!object || object.parent !== grid.frame)
      throw new Error(`move: the file has no moving object '${name}' under its root`);
    const target = new THREE.Vector3(...place.split(',').map(Number));
    object.position.add(target.sub(grid.frame.worldToLocal(objectCentre(object))));
    object.updateMatrixWorld(true);
    updateProbeLight(object, grid);
    blends.push(report(object, 'moved'));
  }
  return blends;
}

async function main() {
  const query = new URLSearchParams(location.search);
  const width = Number(query.get('width') || 640);
  const height = Number(query.get('height') || 480);

  const renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
  const loader = new GLTFLoader();
  loader.register((parser) => new MozLightmapPlugin(parser));
  // A map stored as KTX2 (export --ktx2, KHR_texture_basisu) is read from the KTX2, not the
  // PNG fallback: the Basis transcoder ships with three.
  const ktx2Loader = new KTX2Loader().setTranscoderPath('/three/examples/jsm/libs/basis/');
  loader.setKTX2Loader(ktx2Loader.detectSupport(renderer));
  const gltf = await loader.loadAsync(query.get('file'));
  const patched = addVertexRadiosityAsIrradiance(gltf);
  const directionalPatched = await applyDirectionalLightmaps(gltf);
  // Light groups' weights (LIGHTBAKE_lightmap_groups), in the file's layer order.
  const groupsPatched = query.has('groups')
    ? await applyLightGroups(gltf, query.get('groups').split(',').map(Number))
    : 0;
  const rgbmPatched = decodeRgbmLightmaps(gltf);
  // Moving objects: lit from the file's probe grid where they stand (docs/light-probes.md).
  const grid = loadProbeGrid(gltf);
  const probeLit = applyProbeLight(gltf, grid);
  if (query.has('move') && !grid) throw new Error('move: the file has no probe grid');
  const probeBlends = grid ? moveAndReport(gltf, grid, query) : [];
  if (gltf.cameras.length === 0) throw new Error('the file has no camera');
  const camera = gltf.cameras[0];
  camera.aspect = width / height;  // yfov is vertical in glTF and in lightbake
  camera.updateProjectionMatrix();
  // Exposure: the query's, else the camera's (lightbake writes it in the camera's extras).
  const cameraExtras = gltf.parser.json.cameras[0].extras || {};
  const exposure = query.has('exposure')
    ? Number(query.get('exposure'))
    : Number(cameraExtras.lightbake_exposure_stops || 0);

  renderer.setPixelRatio(1);
  renderer.setSize(width, height);
  renderer.outputColorSpace = THREE.SRGBColorSpace;
  renderer.toneMapping = THREE.LinearToneMapping;  // saturate(2^exposure x radiance)
  renderer.toneMappingExposure = Math.pow(2, exposure);
  document.body.appendChild(renderer.domElement);
  gltf.scene.background = new THREE.Color(0, 0, 0);
  renderer.render(gltf.scene, camera);

  // KTX2 maps, and those read through their own mip chain (export --ktx2 writes the chain and a
  // mipmapped sampler): the levels three.js uploaded and a mip filter on the texture.
  let lightmapped = 0, ktx2 = 0, ktx2Mipmapped = 0, ktx2Levels = 0;
  gltf.scene.traverse((o) => {
    if (!o.isMesh || !o.material.lightMap) return;
    ++lightmapped;
    const map = o.material.lightMap;
    if (!map.isCompressedTexture && !map.isDataTexture) return;
    ++ktx2;
    const levels = (map.mipmaps || []).length;
    if (levels > 1 && map.minFilter === THREE.LinearMipmapLinearFilter) {
      ++ktx2Mipmapped;
      ktx2Levels = Math.max(ktx2Levels, levels);
    }
  });
  window.lightbakeDone = { exposure, lightmapped, colorPatched: patched, revision: THREE.REVISION,
                           rgbmPatched, directionalPatched, groupsPatched, ktx2, ktx2Mipmapped,
                           ktx2Levels, probeLit,
                           probeGrid: !!grid, probeBlends };
}

main().catch((error) => { window.lightbakeError = String(error && error.stack || error); });
