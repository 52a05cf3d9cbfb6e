#include "bake/lightmap/seam_stitch.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <unordered_map>

#include "bake/contact_cuts.h"

namespace lb {

namespace {

struct EdgeRecord {
  size_t mesh = 0, triangle = 0;
  vec3 p0{0.0f}, p1{0.0f};
  vec2 uv0{0.0f}, uv1{0.0f};
  vec3 normal{0.0f};
};

using CellKey = std::tuple<int64_t, int64_t, int64_t>;

CellKey cell_of(vec3 p, float tolerance) {
  const glm::dvec3 q = glm::round(glm::dvec3(p) / double(tolerance));
  return {int64_t(q.x), int64_t(q.y), int64_t(q.z)};
}

void bilinear(int width, int height, vec2 uv, std::array<size_t, 4>& index,
              std::array<float, 4>& weight) {
  const vec2 s = uv * vec2(float(width), float(height)) - 0.5f;
  const vec2 base = glm::floor(s);
  const vec2 f = s - base;
  const int x0 = int(base.x), y0 = int(base.y);
  auto node = [&](int i, int j) {
    return size_t(std::clamp(j, 0, height - 1)) * size_t(width) + size_t(std::clamp(i, 0, width - 1));
  };
  index = {node(x0, y0), node(x0 + 1, y0), node(x0, y0 + 1), node(x0 + 1, y0 + 1)};
  weight = {(1 - f.x) * (1 - f.y), f.x * (1 - f.y), (1 - f.x) * f.y, f.x * f.y};
}

}  // namespace

vec3 bilinear_read(const std::vector<vec3>& values, int width, int height, vec2 uv) {
  std::array<size_t, 4> index;
  std::array<float, 4> weight;
  bilinear(width, height, uv, index, weight);
  vec3 sum(0.0f);
  for (int k = 0; k < 4; ++k) sum += weight[size_t(k)] * values[index[size_t(k)]];
  return sum;
}

std::vector<SeamSample> find_seams(const std::vector<const Mesh*>& meshes, int width, int height,
                                   float tolerance) {
  // Edges by their unordered pair of end-point cells; std::map keeps the order fixed.
  std::map<std::pair<CellKey, CellKey>, std::vector<EdgeRecord>> edges;
  for (size_t m = 0; m < meshes.size(); ++m) {
    const Mesh* mesh = meshes[m];
    if (!mesh || mesh->lightmap_uvs.size() != mesh->positions.size()) continue;
    const bool has_hidden = mesh->hidden.size() == mesh->triangles.size();
    for (size_t t = 0; t < mesh->triangles.size(); ++t) {
      if (has_hidden && mesh->hidden[t]) continue;
      const vec3 n = triangle_normal(*mesh, t);
      if (n == vec3(0.0f)) continue;
      const uvec3 tri = mesh->triangles[t];
      for (int k = 0; k < 3; ++k) {
        const uint32_t a = tri[k], b = tri[(k + 1) % 3];
        EdgeRecord e{m, t, mesh->positions[a], mesh->positions[b], mesh->lightmap_uvs[a],
                     mesh->lightmap_uvs[b], n};
        CellKey ka = cell_of(e.p0, tolerance), kb = cell_of(e.p1, tolerance);
        if (kb < ka) std::swap(ka, kb);
        edges[{ka, kb}].push_back(e);
      }
    }
  }
  const float cos_limit = std::cos(glm::radians(kSeamMaxAngleDeg));
  const vec2 texels{float(width), float(height)};
  std::vector<SeamSample> samples;
  for (const auto& [key, list] : edges)
    for (size_t i = 0; i < list.size(); ++i)
      for (size_t j = i + 1; j < list.size(); ++j) {
        const EdgeRecord& a = list[i];
        EdgeRecord b = list[j];
        if (a.mesh == b.mesh && a.triangle == b.triangle) continue;
        if (glm::dot(a.normal, b.normal) < cos_limit) continue;
        // Orient b like a: its first end point is a's first.
        if (glm::distance(b.p0, a.p0) > glm::distance(b.p1, a.p0)) {
          std::swap(b.p0, b.p1);
          std::swap(b.uv0, b.uv1);
        }
        if (a.uv0 == b.uv0 && a.uv1 == b.uv1) continue;  // one chart: no seam
        const float length = std::max(glm::length((a.uv1 - a.uv0) * texels),
                                      glm::length((b.uv1 - b.uv0) * texels));
        const int n = std::max(1, int(std::ceil(length * kSeamSamplesPerTexel)));
        for (int s = 0; s < n; ++s) {
          const float t = (float(s) + 0.5f) / float(n);
          SeamSample sample;
          bilinear(width, height, glm::mix(a.uv0, a.uv1, t), sample.a, sample.wa);
          bilinear(width, height, glm::mix(b.uv0, b.uv1, t), sample.b, sample.wb);
          samples.push_back(sample);
        }
      }
  return samples;
}

StitchStats stitch_seams(const std::vector<SeamSample>& seams, std::vector<vec3>& values,
                         float seam_weight) {
  StitchStats stats;
  stats.samples = seams.size();
  if (seams.empty()) return stats;
  // The texels the samples read, numbered in node order.
  std::vector<size_t> nodes;
  for (const SeamSample& s : seams)
    for (int k = 0; k < 4; ++k) nodes.push_back(s.a[size_t(k)]), nodes.push_back(s.b[size_t(k)]);
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  std::unordered_map<size_t, uint32_t> local;
  for (size_t k = 0; k < nodes.size(); ++k) local[nodes[k]] = uint32_t(k);
  stats.texels = nodes.size();

  // Each sample's row: read_A - read_B as coefficients on the local unknowns.
  struct Row {
    std::array<uint32_t, 8> var;
    std::array<double, 8> coef;
  };
  std::vector<Row> rows(seams.size());
  for (size_t r = 0; r < seams.size(); ++r)
    for (int k = 0; k < 4; ++k) {
      rows[r].var[size_t(k)] = local[seams[r].a[size_t(k)]];
      rows[r].coef[size_t(k)] = double(seams[r].wa[size_t(k)]);
      rows[r].var[size_t(k) + 4] = local[seams[r].b[size_t(k)]];
      rows[r].coef[size_t(k) + 4] = -double(seams[r].wb[size_t(k)]);
    }
  auto jump = [&](const std::vector<glm::dvec3>& x) {
    double sum = 0.0;
    for (const Row& row : rows) {
      glm::dvec3 d(0.0);
      for (int k = 0; k < 8; ++k) d += row.coef[size_t(k)] * x[row.var[size_t(k)]];
      sum += std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
    }
    return sum / (3.0 * double(rows.size()));
  };
  // y = (I + w A^T A) x over the free unknowns (per channel: `free` 1, or 0 where a texel's
  // channel is held at 0 and drops out of the rows).
  const double w = seam_weight;
  std::vector<glm::dvec3> free(nodes.size(), glm::dvec3(1.0));
  auto apply = [&](const std::vector<glm::dvec3>& x, std::vector<glm::dvec3>& y) {
    y = x;
    for (const Row& row : rows) {
      glm::dvec3 d(0.0);
      for (int k = 0; k < 8; ++k) {
        const uint32_t v = row.var[size_t(k)];
        d += row.coef[size_t(k)] * free[v] * x[v];
      }
      for (int k = 0; k < 8; ++k) {
        const uint32_t v = row.var[size_t(k)];
        y[v] += w * row.coef[size_t(k)] * free[v] * d;
      }
    }
  };
  std::vector<glm::dvec3> x0(nodes.size());
  for (size_t k = 0; k < nodes.size(); ++k) x0[k] = glm::dvec3(values[nodes[k]]);
  stats.jump_before = jump(x0);

  auto dot = [](const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b) {
    glm::dvec3 s(0.0);
    for (size_t k = 0; k < a.size(); ++k) s += a[k] * b[k];
    return s;
  };
  // Conjugate gradients from x, the three channels side by side (each its own scalars).
  const glm::dvec3 stop = 1e-12 * glm::max(dot(x0, x0), glm::dvec3(1e-30));
  constexpr int kMaxIterations = 500;
  auto solve = [&](std::vector<glm::dvec3>& x) {
    std::vector<glm::dvec3> r(x.size()), p, q;
    apply(x, q);
    for (size_t k = 0; k < x.size(); ++k) r[k] = free[k] * x0[k] - q[k];
    p = r;
    glm::dvec3 rr = dot(r, r);
    for (int iteration = 0; iteration < kMaxIterations; ++iteration, ++stats.iterations) {
      if (glm::all(glm::lessThanEqual(rr, stop))) break;
      apply(p, q);
      const glm::dvec3 pq = dot(p, q);
      glm::dvec3 alpha;
      for (int c = 0; c < 3; ++c) alpha[c] = pq[c] > 0.0 ? rr[c] / pq[c] : 0.0;
      for (size_t k = 0; k < x.size(); ++k) x[k] += alpha * p[k], r[k] -= alpha * q[k];
      const glm::dvec3 rr_next = dot(r, r);
      glm::dvec3 beta;
      for (int c = 0; c < 3; ++c) beta[c] = rr[c] > 0.0 ? rr_next[c] / rr[c] : 0.0;
      for (size_t k = 0; k < p.size(); ++k) p[k] = r[k] + beta * p[k];
      rr = rr_next;
    }
  };
  // Light is never negative. Where a seam runs along a shadow's edge, the bright side's texels
  // outside its chart would go below 0 to meet the dark side (and clamping them undid the
  // stitch there: reads 30% apart); so such channels are held at 0 and the rest solved again,
  // until none goes below 0 (an active set: the least squares under x >= 0).
  std::vector<glm::dvec3> x = x0;
  constexpr int kMaxRounds = 16;
  for (int round = 0; round < kMaxRounds; ++round) {
    solve(x);
    bool held = false;
    for (size_t k = 0; k < x.size(); ++k)
      for (int c = 0; c < 3; ++c)
        if (x[k][c] < 0.0) free[k][c] = 0.0, x[k][c] = 0.0, held = true;
    if (!held) break;
  }
  for (glm::dvec3& v : x) v = glm::max(v, glm::dvec3(0.0));
  stats.jump_after = jump(x);
  for (size_t k = 0; k < nodes.size(); ++k) values[nodes[k]] = vec3(x[k]);
  return stats;
}

std::vector<SeamSample> atlas_seams(const Scene& scene, const IlluminationMaps& maps) {
  std::vector<Mesh> charted;
  charted.reserve(scene.meshes.size());  // pointers into it stay valid
  std::vector<const Mesh*> meshes(scene.meshes.size(), nullptr);
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    if (m < maps.lightmap_uvs.size() && !maps.lightmap_uvs[m].empty()) {
      charted.push_back(mesh_with_lightmap(scene.meshes[m], maps, m));
      meshes[m] = &charted.back();
    }
  return find_seams(meshes, maps.width, maps.height, contact_tolerance(scene));
}

}  // namespace lb
