// three.js side of lightbake's export (docs/export.md, "three.js"): a GLTFLoader plugin that
// binds MOZ_lightmap as the material's lightMap, and the patch that adds COLOR_0 (vertex
// radiosity) to the irradiance instead of tinting the albedo. Both keep the file's convention:
// rendered radiance = albedo x (direct + lightmap + COLOR_0), the baked terms stored as E/pi.
import * as THREE from 'three';
import { objectCentre, vertexProbeLight } from './probe_grid.js';

// loader.register((parser) => new MozLightmapPlugin(parser))
export class MozLightmapPlugin {
  constructor(parser) {
    this.parser = parser;
    this.name = 'MOZ_lightmap';
  }

  extendMaterialParams(materialIndex, params) {
    const def = this.parser.json.materials[materialIndex];
    const ext = def.extensions && def.extensions[this.name];
    if (!ext) return Promise.resolve();
    // three adds texel x lightMapIntensity to the irradiance and multiplies the irradiance by
    // albedo / pi, so intensity = pi x scale gives albedo x E/pi (the exporter writes it so).
    params.lightMapIntensity = ext.intensity !== undefined ? ext.intensity : 1;
    // 'srgb8-scaled': the PNG's bytes are sRGB-encoded, so three must decode them to linear
    // (in the sampler, before filtering); any other encoding is taken as linear values.
    const extras = (def.extras && def.extras.lightbake_lightmap) || {};
    const srgb = String(extras.encoding || 'srgb8-scaled').startsWith('srgb');
    const colorSpace = srgb ? THREE.SRGBColorSpace : THREE.LinearSRGBColorSpace;
    const texCoord = ext.texCoord !== undefined ? ext.texCoord : 1;
    return this.parser
      .assignTexture(params, 'lightMap', { index: ext.index, texCoord }, colorSpace)
      .then((texture) => {
        if (!texture) return;
        texture.channel = texCoord;  // TEXCOORD_1 is GLTFLoader's attribute `uv1`
        texture.flipY = false;       // glTF images: row 0 is v = 0
      });
  }
}

// LIGHTBAKE_lightmap_directional (lightbake export --directional; docs/export.md, "Directional
// maps"): the map's L1 band, three RGB textures (world axes x, y, z) holding L1 / L0 per
// channel as byte = 128 + 127 r; with "share": true (export --directional-share) the x
// texture's alpha holds s (the direct term's share of L0), else s = 0 (a file without the
// key, written before it, has s there too). The shader chunk takes the baked light at the
// shading normal n (normal map included) with the unbumped normal n0, both in world axes:
//   E(n)/pi = max(0, L0 (1 - W (1 - n . n0) + r_x n_x + r_y n_y + r_z n_z)),  W = (1 + s) / 2.
// Copy this chunk to any engine that draws MOZ_lightmap. Call after loading, before
// decodeRgbmLightmaps (it decodes RGBM itself). Resolves to the number of materials patched.
export const directionalLightmapChunk = `
uniform sampler2D lightbakeL1x;
uniform sampler2D lightbakeL1y;
uniform sampler2D lightbakeL1z;
uniform float lightbakeShare;  // 1: s in the x map's alpha ("share": true), 0: s = 0
vec3 lightbakeDirectional(vec3 l0, vec3 viewNormal, vec3 viewNormal0) {
  vec3 n = normalize((vec4(viewNormal, 0.0) * viewMatrix).xyz);  // world axes
  vec3 n0 = normalize((vec4(viewNormal0, 0.0) * viewMatrix).xyz);  // without the normal map
  vec4 x = texture2D(lightbakeL1x, vLightMapUv);
  vec3 rx = x.rgb * (255.0 / 127.0) - 128.0 / 127.0;
  vec3 ry = texture2D(lightbakeL1y, vLightMapUv).rgb * (255.0 / 127.0) - 128.0 / 127.0;
  vec3 rz = texture2D(lightbakeL1z, vLightMapUv).rgb * (255.0 / 127.0) - 128.0 / 127.0;
  float w = 0.5 + 0.5 * lightbakeShare * x.a;
  return max(l0 * (1.0 - w * (1.0 - dot(n, n0)) + rx * n.x + ry * n.y + rz * n.z), 0.0);
}
`;

export async function applyDirectionalLightmaps(gltf) {
  const parser = gltf.parser;
  const name = 'LIGHTBAKE_lightmap_directional';
  const materials = new Set();
  gltf.scene.traverse((object) => {
    if (object.isMesh && object.material.lightMap) materials.add(object.material);
  });
  let patched = 0;
  for (const material of materials) {
    const association = parser.associations.get(material);
    if (!association || association.materials === undefined) continue;
    const def = parser.json.materials[association.materials];
    const ext = def.extensions && def.extensions[name];
    if (!ext || material.userData.lightbakeDirectional) continue;
    const textures = await Promise.all(ext.l1.map((t) => parser.getDependency('texture', t.index)));
    for (const texture of textures) {
      texture.channel = 1;  // TEXCOORD_1
      texture.flipY = false;
      texture.colorSpace = THREE.NoColorSpace;  // ratios, linear bytes
      texture.needsUpdate = true;
    }
    const rgbm = (material.userData.lightbake_lightmap || {}).encoding === 'rgbm8';
    material.userData.lightbakeDirectional = true;
    material.userData.lightbakeRgbm = true;  // decoded here
    material.onBeforeCompile = (shader) => {
      shader.uniforms.lightbakeL1x = { value: textures[0] };
      shader.uniforms.lightbakeL1y = { value: textures[1] };
      shader.uniforms.lightbakeL1z = { value: textures[2] };
      shader.uniforms.lightbakeShare = { value: ext.share === false ? 0.0 : 1.0 };
      const l0 = rgbm ? 'lightMapTexel.rgb * lightMapTexel.a' : 'lightMapTexel.rgb';
      shader.fragmentShader = shader.fragmentShader
        .replace('#include <lights_pars_begin>',
                 '#include <lights_pars_begin>\n' + directionalLightmapChunk)
        .replace('#include <lights_fragment_maps>',
                 THREE.ShaderChunk.lights_fragment_maps.replace(
                   'lightMapTexel.rgb * lightMapIntensity',
                   `lightbakeDirectional(${l0}, normal, nonPerturbedNormal) * lightMapIntensity`));
    };
    material.customProgramCacheKey = () => 'lightbake_directional' + (rgbm ? '_rgbm8' : '');
    material.needsUpdate = true;
    ++patched;
  }
  return patched;
}

// LIGHTBAKE_lightmap_groups (a bake with light groups; docs/export.md, "Light groups"): one
// lightmap layer per group, each with its own intensity; the baked light is the sum over layers
// of weight x intensity x texel, in place of MOZ_lightmap's (the sum at weight 1). `weights`
// in the layers' order (missing: the layer's own `weight`). Emitters whose material names a
// group (extras.lightbake_group) glow with its weight too. Uniforms, so a game moves them per
// frame: material.userData.lightbakeGroupScales[g].value = w x intensity. sRGB encoding only
// (RGBM layers would need the alpha decode). Resolves to the number of materials patched.
export async function applyLightGroups(gltf, weights) {
  const parser = gltf.parser;
  const name = 'LIGHTBAKE_lightmap_groups';
  const weightOf = new Map();
  let patched = 0;
  const materials = new Set();
  gltf.scene.traverse((object) => {
    if (object.isMesh) materials.add(object.material);
  });
  for (const material of materials) {
    const association = parser.associations.get(material);
    if (!association || association.materials === undefined) continue;
    const def = parser.json.materials[association.materials];
    const ext = def.extensions && def.extensions[name];
    if (!ext || !material.lightMap || material.userData.lightbakeGroups) continue;
    const layers = ext.layers;
    layers.forEach((layer, g) => {
      weightOf.set(layer.name, weights[g] !== undefined ? weights[g] : layer.weight);
    });
    const textures = await Promise.all(layers.map((l) => parser.getDependency('texture', l.index)));
    for (const texture of textures) {
      texture.channel = 1;  // TEXCOORD_1
      texture.flipY = false;
      texture.colorSpace = THREE.SRGBColorSpace;  // srgb8-scaled, decoded by the sampler
      texture.needsUpdate = true;
    }
    const scales = layers.map((l) => ({ value: weightOf.get(l.name) * l.intensity }));
    material.userData.lightbakeGroups = true;
    material.userData.lightbakeGroupScales = scales;
    const declarations = layers.map((_, g) =>
      `uniform sampler2D lightbakeGroup${g};\nuniform float lightbakeGroupScale${g};`).join('\n');
    const sum = layers.map((_, g) =>
      `texture2D(lightbakeGroup${g}, vLightMapUv).rgb * lightbakeGroupScale${g}`).join(' + ');
    material.onBeforeCompile = (shader) => {
      textures.forEach((texture, g) => {
        shader.uniforms[`lightbakeGroup${g}`] = { value: texture };
        shader.uniforms[`lightbakeGroupScale${g}`] = scales[g];
      });
      shader.fragmentShader = shader.fragmentShader
        .replace('#include <lights_pars_begin>', '#include <lights_pars_begin>\n' + declarations)
        .replace('#include <lights_fragment_maps>',
                 THREE.ShaderChunk.lights_fragment_maps.replace(
                   'lightMapTexel.rgb * lightMapIntensity', `(${sum})`));
    };
    material.customProgramCacheKey = () => `lightbake_groups_${layers.length}`;
    material.needsUpdate = true;
    ++patched;
  }
  // The groups' emitters.
  for (const material of materials) {
    const group = material.userData.lightbake_group;
    if (group !== undefined && weightOf.has(group) && material.emissiveIntensity !== undefined)
      material.emissiveIntensity *= weightOf.get(group);
  }
  return patched;
}

// 'rgbm8' lightmaps (lightbake export --lightmap-encoding rgbm): linear RGB x alpha x scale,
// decoded in the shader (MOZ_lightmap.intensity = pi x scale, as for srgb8-scaled). Applied to
// the materials after loading: GLTFLoader clones a material for meshes without tangents, and a
// clone does not keep onBeforeCompile. Returns the number of materials patched.
export function decodeRgbmLightmaps(gltf) {
  let patched = 0;
  gltf.scene.traverse((object) => {
    if (!object.isMesh || !object.material.lightMap) return;
    const material = object.material;
    const extras = material.userData.lightbake_lightmap || {};
    if (extras.encoding !== 'rgbm8' || material.userData.lightbakeRgbm) return;
    material.userData.lightbakeRgbm = true;
    material.onBeforeCompile = (shader) => {
      shader.fragmentShader = shader.fragmentShader.replace(
        '#include <lights_fragment_maps>',
        THREE.ShaderChunk.lights_fragment_maps.replace(
          'lightMapTexel.rgb * lightMapIntensity',
          'lightMapTexel.rgb * lightMapTexel.a * lightMapIntensity'));
    };
    material.customProgramCacheKey = () => 'lightbake_rgbm8';
    ++patched;
  });
  return patched;
}

// COLOR_0 of a lightbake file is light (E/pi / lightbake_color_0_scale), not colour: GLTFLoader
// turns on vertexColors, which would multiply it into the albedo. Keep the attribute but add
// vColor x pi x scale to the irradiance, as the lightmap is added.
export function addVertexRadiosityAsIrradiance(gltf) {
  const extras = gltf.parser.json.asset.extras || {};
  if (extras.lightbake_color_0_scale === undefined) return 0;  // not a lightbake file
  const intensity = Math.PI * extras.lightbake_color_0_scale;
  let patched = 0;
  gltf.scene.traverse((object) => {
    if (!object.isMesh || !object.geometry.attributes.color || !object.material.vertexColors)
      return;
    const material = object.material;  // GLTFLoader's vertex-colour variant, meshes with COLOR_0
    if (material.userData.lightbakeColor0) return;
    material.userData.lightbakeColor0 = true;
    material.onBeforeCompile = (shader) => {
      shader.uniforms.lightbakeColor0Intensity = { value: intensity };
      shader.fragmentShader =
        'uniform float lightbakeColor0Intensity;\n' +
        shader.fragmentShader
          .replace('#include <color_fragment>', '')
          .replace(
            '#include <lights_fragment_maps>',
            '#include <lights_fragment_maps>\n' +
              '\tirradiance += vColor.rgb * lightbakeColor0Intensity;'
          );
    };
    material.customProgramCacheKey = () => 'lightbake_color_0';
    ++patched;
  });
  return patched;
}

// Moving objects (docs/light-probes.md, "Blending the grid in an engine"): each mesh of a node
// with extras.dynamic is lit from the file's probe grid (`grid`, probe_grid.js's loadProbeGrid)
// per vertex where it stands now: the grid blended at each vertex (vertexProbeLight), E/pi at
// the vertex's normal, in a vertex attribute `lightbakeProbeLight` interpolated across the
// triangles; the blend at the mesh's centre goes in a uniform for the detail a normal map turns
// the shading normal by (E_centre(n) - E_centre(n0), nothing on a smooth surface), as our
// viewer's shader (PROBE_LIT, HAS_VERTEX_RADIANCE). When the file has no grid or `grid` is
// null: the node's extras.lightbake_probe_sh (the centre's blend at the exported place) alone,
// at the pixel's normal. The light (L2 SH of the incident radiance, three's
// SphericalHarmonics3 order and normalisation) is added to the irradiance exactly as three's
// own LightProbe is (shGetIrradianceAt), for that object alone. After moving an object,
// updateProbeLight(object, grid). Returns the number of meshes patched.
export const probeLightVertexChunk = `
attribute vec3 lightbakeProbeLight;
varying vec3 vLightbakeProbeLight;`;
export const probeLightFragmentChunk = `
uniform vec3 lightbakeProbeSh[9];
uniform float lightbakePerVertex;  // 1: vLightbakeProbeLight holds E/pi a vertex
varying vec3 vLightbakeProbeLight;`;

export function applyProbeLight(gltf, grid) {
  let patched = 0;
  gltf.scene.traverse((object) => {
    const extras = object.userData || {};
    if (!object.isMesh || !extras.dynamic) return;
    const sh = new THREE.SphericalHarmonics3();
    const perVertex = !!grid;
    if (grid) sh.fromArray(grid.blend(objectCentre(object)).sh);
    else if (Array.isArray(extras.lightbake_probe_sh)) sh.fromArray(extras.lightbake_probe_sh);
    else return;
    const count = object.geometry.attributes.position.count;
    object.geometry = object.geometry.clone();  // the attribute is this object's alone
    object.geometry.setAttribute('lightbakeProbeLight', new THREE.BufferAttribute(
      perVertex ? vertexProbeLight(object, grid) : new Float32Array(3 * count), 3));
    const material = object.material.clone();  // for this object alone
    material.onBeforeCompile = (shader) => {
      shader.uniforms.lightbakeProbeSh = { value: sh.coefficients };
      shader.uniforms.lightbakePerVertex = { value: perVertex ? 1 : 0 };
      shader.vertexShader = probeLightVertexChunk + '\n' + shader.vertexShader.replace(
        '#include <begin_vertex>',
        '#include <begin_vertex>\n\tvLightbakeProbeLight = lightbakeProbeLight;');
      // Per vertex: E_vertex + E_centre(n) - E_centre(n0), clamped at 0; else E_centre(n).
      shader.fragmentShader = probeLightFragmentChunk + '\n' + shader.fragmentShader.replace(
        '#include <lights_fragment_maps>',
        '#include <lights_fragment_maps>\n' +
          '\tvec3 lightbakeProbe = shGetIrradianceAt(' +
          'inverseTransformDirection(normal, viewMatrix), lightbakeProbeSh);\n' +
          '\tif (lightbakePerVertex > 0.5) lightbakeProbe = max(PI * vLightbakeProbeLight + ' +
          'lightbakeProbe - shGetIrradianceAt(' +
          'inverseTransformDirection(nonPerturbedNormal, viewMatrix), lightbakeProbeSh), 0.0);\n' +
          '\tirradiance += lightbakeProbe;');
    };
    material.customProgramCacheKey = () => 'lightbake_probe';
    object.material = material;
    object.userData.lightbakeProbeSh = sh;  // the uniform's value: updated in place
    ++patched;
  });
  return patched;
}

// Blends `grid` again where a probe-lit object stands now (call after moving it): at each of
// its vertices into its `lightbakeProbeLight` attribute, and at its centre into the uniform;
// returns the centre's blend (probe_grid.js: sh, probes, ring).
export function updateProbeLight(object, grid) {
  const blend = grid.blend(objectCentre(object));
  object.userData.lightbakeProbeSh.fromArray(blend.sh);
  const attribute = object.geometry.attributes.lightbakeProbeLight;
  attribute.array.set(vertexProbeLight(object, grid));
  attribute.needsUpdate = true;
  return blend;
}
