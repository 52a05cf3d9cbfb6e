// lightbake's light-probe grid in three.js (docs/light-probes.md, "In the exported file"): reads
// scene.extensions.LIGHTBAKE_light_probes and blends it at any point, by the rule of the C++
// blend (blend_probes, bake/probe_grid.cpp), so a moving object gets the light of where it is
// now. Copy this file to light moving objects from a lightbake export:
//   const grid = loadProbeGrid(gltf);          // null when the file has no grid
//   const { sh } = grid.blend(worldPoint);      // 27 numbers: three's SphericalHarmonics3 order
//   lightProbe.sh.fromArray(sh);                // or a per-object uniform (moz_lightmap.js)
// The rule: trilinear weights over the 8 probes of the cell around the point, leaving out
// invalid probes and probes the point cannot see (a ray through the file's static meshes: what
// keeps light from leaking through a wall), the rest renormalised; when none of the 8 remains,
// the ring around them (the 4 x 4 x 4 block, then 6 x 6 x 6, ...) with inverse-square-distance
// weights. Visibility uses three's Raycaster over every mesh (no BVH): fine for a blend per
// object per frame in a small scene; a large one wants three-mesh-bvh's accelerated raycast.
import * as THREE from 'three';

export const probeGridExtension = 'LIGHTBAKE_light_probes';

// Ray ends as the C++ offset_ray_origin (bake/accel.cpp) places them: moved along the unit
// direction by 256 float ULPs per unit of each component, or 1/65536 m per unit near the
// origin (|coordinate| < 1/32), so a ray neither starts nor ends inside the surface a point
// rests on. Float32 arithmetic, as in C++.
const floatBits = new Float32Array(1);
const intBits = new Int32Array(floatBits.buffer);
function offsetAlong(point, direction) {
  const f = Math.fround;
  return point.map((p, k) => {
    const n = direction[k];
    if (Math.abs(p) < 1 / 32) return f(p + f(n / 65536));
    const ulps = Math.trunc(f(256 * n));
    floatBits[0] = p;
    intBits[0] += p < 0 ? -ulps : ulps;
    return floatBits[0];
  });
}

export class ProbeGrid {
  // `json`: the extension's object; `frame`: the Object3D its coordinates are in (the file's
  // root node, `lightbake`); `staticMeshes`: the meshes that block light (every mesh of the
  // file but the moving ones), each at its current matrixWorld.
  constructor(json, frame, staticMeshes) {
    this.origin = json.origin.map(Math.fround);
    this.spacing = json.spacing.map(Math.fround);
    this.counts = json.counts.slice();
    this.valid = Uint8Array.from(json.valid);
    this.coefficients = Float32Array.from(json.coefficients);
    const size = this.counts[0] * this.counts[1] * this.counts[2];
    if (this.valid.length !== size || this.coefficients.length !== 27 * size)
      throw new Error(`${probeGridExtension}: ${size} probes, but ${this.valid.length} valid ` +
                      `flags and ${this.coefficients.length} coefficients (27 a probe)`);
    this.frame = frame;
    frame.updateWorldMatrix(true, false);
    const toFrame = frame.matrixWorld.clone().invert();
    // Copies that see both faces (Embree's rays hit either side; three's skip a FrontSide
    // material's backs), placed in the grid's frame.
    const material = new THREE.MeshBasicMaterial({ side: THREE.DoubleSide });
    this.occluders = staticMeshes.map((mesh) => {
      mesh.updateWorldMatrix(true, false);
      const copy = new THREE.Mesh(mesh.geometry, material);
      copy.matrixAutoUpdate = false;
      copy.matrixWorld.multiplyMatrices(toFrame, mesh.matrixWorld);
      return copy;
    });
    this.raycaster = new THREE.Raycaster();
  }

  // Probe (i, j, k) is entry i + nx (j + ny k).
  index(i, j, k) { return i + this.counts[0] * (j + this.counts[1] * k); }
  position(i, j, k) {
    const f = Math.fround;
    return [i, j, k].map((c, a) => f(this.origin[a] + f(c * this.spacing[a])));
  }

  // Whether `point` sees the probe at `probe` (both in the grid's frame): the segment between
  // them, its ends offset as in C++, meets no static mesh.
  sees(point, probe) {
    const f = Math.fround;
    const d = probe.map((p, a) => f(p - point[a]));
    const squared = f(f(d[0] * d[0]) + f(d[1] * d[1]) + f(d[2] * d[2]));
    if (squared < 1e-12) return true;
    const length = f(Math.sqrt(squared));
    const direction = d.map((c) => f(c / length));
    const from = offsetAlong(point, direction);
    const to = offsetAlong(probe, direction.map((c) => -c));
    const ray = new THREE.Vector3(to[0] - from[0], to[1] - from[1], to[2] - from[2]);
    const far = ray.length();
    if (far === 0) return true;
    this.raycaster.set(new THREE.Vector3(...from), ray.divideScalar(far));
    this.raycaster.near = 0;
    this.raycaster.far = far;
    return this.raycaster.intersectObjects(this.occluders, false).length === 0;
  }

  // The blended light at `worldPoint` (a THREE.Vector3): { sh: 27 numbers (coefficient 0's
  // R, G, B, then coefficient 1's, ...; docs/light-probes.md's convention), probes: how many
  // took part, ring: 0 for the 8 around the point, r for the (2r + 2)^3 block, -1 for none (sh
  // all 0) }. `occlusion: false` skips the visibility rays (a plain blend of the valid probes,
  // which leaks light through walls: for comparison only).
  blend(worldPoint, { occlusion = true } = {}) {
    const f = Math.fround;
    const local = this.frame.worldToLocal(worldPoint.clone());
    const point = [local.x, local.y, local.z].map(f);
    const last = this.counts.map((n) => n - 1);
    const fraction = point.map((p, a) => f(f(p - this.origin[a]) / this.spacing[a]));
    const base = fraction.map((q, a) =>
      Math.min(Math.max(Math.floor(q), 0), Math.max(last[a] - 1, 0)));
    const t = fraction.map((q, a) => Math.min(Math.max(f(q - base[a]), 0), 1));
    const rings = Math.max(...this.counts);
    for (let ring = 0; ring <= rings; ++ring) {
      const sum = new Float64Array(27);
      let total = 0, used = 0;
      const lo = base.map((b) => b - ring), hi = base.map((b) => b + 1 + ring);
      for (let k = Math.max(lo[2], 0); k <= Math.min(hi[2], last[2]); ++k)
        for (let j = Math.max(lo[1], 0); j <= Math.min(hi[1], last[1]); ++j)
          for (let i = Math.max(lo[0], 0); i <= Math.min(hi[0], last[0]); ++i) {
            const cell = [i, j, k];
            // Ring r's probes are its block's outside ring r - 1's (already refused).
            if (ring > 0 && cell.every((c, a) => c > lo[a] && c < hi[a])) continue;
            const position = this.position(i, j, k);
            let weight;
            if (ring === 0) {
              const w = cell.map((c, a) => {
                const d = c - base[a];
                return f(f(d * t[a]) + f((1 - d) * f(1 - t[a])));
              });
              // A floor, so the renormalised blend still has a direction when the point sits
              // on a refused probe and the others' trilinear weights are all 0.
              weight = Math.max(w[0] * w[1] * w[2], 1e-4);
            } else {
              const d = position.map((p, a) => f(f(p - point[a]) / this.spacing[a]));
              weight = 1 / (1e-6 + f(f(f(d[0] * d[0]) + f(d[1] * d[1])) + f(d[2] * d[2])));
            }
            const p = this.index(i, j, k);
            if (!this.valid[p] || (occlusion && !this.sees(point, position))) continue;
            for (let c = 0; c < 27; ++c) sum[c] += weight * this.coefficients[27 * p + c];
            total += weight;
            ++used;
          }
      if (used === 0) {
        if (lo.every((l) => l <= 0) && hi.every((h, a) => h >= last[a])) break;
        continue;  // the block does not cover the grid yet: a wider ring
      }
      return { sh: Array.from(sum, (s) => s / total), probes: used, ring };
    }
    return { sh: new Array(27).fill(0), probes: 0, ring: -1 };
  }
}

// The file's grid, with its frame (the file's root node, `lightbake`, above every mesh) and
// its static meshes (no extras.dynamic on them or a node above them); null when the file has
// none.
export function loadProbeGrid(gltf) {
  const json = gltf.parser.json;
  const scene = json.scenes[json.scene || 0];
  const ext = scene.extensions && scene.extensions[probeGridExtension];
  if (!ext) return null;
  const staticMeshes = [];
  let frame = gltf.scene;
  gltf.scene.traverse((object) => {
    if (!object.isMesh) return;
    let dynamic = !!object.userData.dynamic, root = object;
    while (root.parent && root.parent !== gltf.scene) {
      root = root.parent;
      dynamic = dynamic || !!root.userData.dynamic;
    }
    if (!dynamic) staticMeshes.push(object);
    if (root.parent === gltf.scene) frame = root;
  });
  return new ProbeGrid(ext, frame, staticMeshes);
}

// The centre of an object's world-space bounding box over its vertices (as the C++
// mesh_centre), where its light is blended.
export function objectCentre(object) {
  return new THREE.Box3().setFromObject(object, true).getCenter(new THREE.Vector3());
}

// E(n) in W/m^2 from 27 blended numbers at a unit normal n (an array of 3, the grid's axes),
// clamped at 0 per channel, as the C++ sh_irradiance (bake/probe_grid.cpp): the cosine lobe's
// band weights pi, 2 pi / 3, pi / 4 times the coefficients times Y_lm(n).
export function shIrradiance(sh, n) {
  const [x, y, z] = n;
  const basis = [0.282095, 0.488603 * y, 0.488603 * z, 0.488603 * x, 1.092548 * x * y,
                 1.092548 * y * z, 0.315392 * (3 * z * z - 1), 1.092548 * x * z,
                 0.546274 * (x * x - y * y)];
  const band = [Math.PI, 2 * Math.PI / 3, 2 * Math.PI / 3, 2 * Math.PI / 3, Math.PI / 4,
                Math.PI / 4, Math.PI / 4, Math.PI / 4, Math.PI / 4];
  return [0, 1, 2].map((c) => {
    let e = 0;
    for (let k = 0; k < 9; ++k) e += band[k] * sh[3 * k + c] * basis[k];
    return Math.max(e, 0);
  });
}

// The light of a moving mesh per vertex, as the C++ reader draws it (vertex_probe_light,
// bake/probes/dynamic_light.h): at each vertex, the grid blended at the vertex's world
// position lifted 1% of the smallest spacing along its world normal (so that its visibility
// rays do not start inside a static surface it rests on), and E/pi at that normal from the
// blend. Returns a Float32Array of RGB triples (W/(sr m^2)), one a vertex; all 0 for a mesh
// without normals. Up to 8 rays a vertex (three's raycaster): re-run when the object moves.
export function vertexProbeLight(object, grid) {
  const positions = object.geometry.attributes.position;
  const normals = object.geometry.attributes.normal;
  const out = new Float32Array(3 * positions.count);
  if (!normals) return out;
  object.updateWorldMatrix(true, false);
  const toGrid = new THREE.Matrix3().getNormalMatrix(
    grid.frame.matrixWorld.clone().invert().multiply(object.matrixWorld));
  const toWorld = new THREE.Matrix3().getNormalMatrix(object.matrixWorld);
  const lift = 0.01 * Math.min(...grid.spacing);
  const p = new THREE.Vector3(), n = new THREE.Vector3(), m = new THREE.Vector3();
  for (let v = 0; v < positions.count; ++v) {
    p.fromBufferAttribute(positions, v).applyMatrix4(object.matrixWorld);
    n.fromBufferAttribute(normals, v).applyMatrix3(toWorld).normalize();
    m.fromBufferAttribute(normals, v).applyMatrix3(toGrid).normalize();  // the grid's axes
    const { sh } = grid.blend(p.addScaledVector(n, lift));
    const e = shIrradiance(sh, [m.x, m.y, m.z]);
    for (let c = 0; c < 3; ++c) out[3 * v + c] = e[c] / Math.PI;
  }
  return out;
}
