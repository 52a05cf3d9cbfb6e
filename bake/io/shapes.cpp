#include "bake/io/shapes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "bake/constants.h"

namespace lb {

namespace {

struct GridVertex {
  vec3 position;
  vec3 normal;
  vec2 uv;
};

// Twice the area of a triangle below this fraction of its longest edge squared counts as
// degenerate; validate_scene uses a smaller fraction, so shapes never trip its warning.
constexpr float kShapeDegenerateRatio = 1e-6f;

bool nearly_degenerate(vec3 a, vec3 b, vec3 c) {
  const float longest =
      std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
  return glm::length(glm::cross(b - a, c - a)) <= kShapeDegenerateRatio * longest;
}

// Adds a (rows+1) x (cols+1) grid of vertices from `vertex(i, j)` and two triangles per cell,
// each wound so its front agrees with the shading normals; collapsed cells (poles) are skipped.
template <class VertexFn>
void add_grid(Mesh& mesh, int rows, int cols, VertexFn vertex) {
  const uint32_t base = uint32_t(mesh.positions.size());
  for (int i = 0; i <= rows; ++i)
    for (int j = 0; j <= cols; ++j) {
      const GridVertex v = vertex(i, j);
      mesh.positions.push_back(v.position);
      mesh.normals.push_back(glm::normalize(v.normal));
      mesh.uvs.push_back(v.uv);
    }
  const uint32_t stride = uint32_t(cols + 1);
  auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
    const vec3 pa = mesh.positions[a], pb = mesh.positions[b], pc = mesh.positions[c];
    if (nearly_degenerate(pa, pb, pc)) return;
    const vec3 shading = mesh.normals[a] + mesh.normals[b] + mesh.normals[c];
    if (glm::dot(glm::cross(pb - pa, pc - pa), shading) < 0.0f) std::swap(b, c);
    mesh.triangles.push_back({a, b, c});
  };
  for (uint32_t i = 0; i < uint32_t(rows); ++i)
    for (uint32_t j = 0; j < uint32_t(cols); ++j) {
      const uint32_t a = base + i * stride + j, b = a + 1, d = a + stride, c = d + 1;
      emit(a, b, c);
      emit(a, c, d);
    }
}

// cos/sin that are exact at multiples of a quarter turn, so poles and seams coincide exactly.
vec2 unit_circle(int step, int steps) {
  if (step == 0 || step == steps) return {1.0f, 0.0f};
  if (4 * step == steps) return {0.0f, 1.0f};
  if (2 * step == steps) return {-1.0f, 0.0f};
  if (4 * step == 3 * steps) return {0.0f, -1.0f};
  const float angle = 2.0f * kPi * float(step) / float(steps);
  return {std::cos(angle), std::sin(angle)};
}

// A flat ring between `inner` and `outer` radius at height y facing +Y (`up`) or -Y; a disc
// when `inner` is 0. UVs are planar over the outer diameter.
void add_annulus(Mesh& mesh, float inner, float outer, float y, int segments, bool up) {
  add_grid(mesh, 1, segments, [&](int i, int j) {
    const vec2 c = unit_circle(j, segments);
    const float r = i == 0 ? outer : inner;
    const vec3 p(r * c.x, y, r * c.y);
    return GridVertex{p, vec3(0.0f, up ? 1.0f : -1.0f, 0.0f),
                      vec2(0.5f + p.x / (2.0f * outer), 0.5f + p.z / (2.0f * outer))};
  });
}

// A cylindrical wall of radius r from y0 to y1, normals out (or in).
void add_wall(Mesh& mesh, float r, float y0, float y1, int segments, bool outward) {
  add_grid(mesh, 1, segments, [&](int i, int j) {
    const vec2 c = unit_circle(j, segments);
    const vec3 n(c.x, 0.0f, c.y);
    return GridVertex{vec3(r * c.x, i == 0 ? y0 : y1, r * c.y), outward ? n : -n,
                      vec2(float(j) / float(segments), float(1 - i))};
  });
}

// Merges vertices whose position, normal and UV are bitwise equal (shared ring seams).
void weld_identical(Mesh& mesh) {
  using Key = std::tuple<float, float, float, float, float, float, float, float>;
  std::map<Key, uint32_t> index_of;
  std::vector<uint32_t> remap(mesh.positions.size());
  Mesh welded;
  welded.name = mesh.name;
  welded.material = mesh.material;
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const vec3 p = mesh.positions[v], n = mesh.normals[v];
    const vec2 t = mesh.uvs[v];
    const auto [it, inserted] = index_of.try_emplace(Key{p.x, p.y, p.z, n.x, n.y, n.z, t.x, t.y},
                                                     uint32_t(welded.positions.size()));
    if (inserted) {
      welded.positions.push_back(p);
      welded.normals.push_back(n);
      welded.uvs.push_back(t);
    }
    remap[v] = it->second;
  }
  for (uvec3 t : mesh.triangles) welded.triangles.push_back({remap[t.x], remap[t.y], remap[t.z]});
  mesh = std::move(welded);
}

}  // namespace

Mesh make_quad_corners(vec3 origin, vec3 edge_u, vec3 edge_v, float uv_tile) {
  Mesh mesh;
  mesh.positions = {origin, origin + edge_u, origin + edge_u + edge_v, origin + edge_v};
  mesh.normals.assign(4, glm::normalize(glm::cross(edge_u, edge_v)));
  const vec2 extent =
      uv_tile > 0.0f ? vec2(glm::length(edge_u), glm::length(edge_v)) / uv_tile : vec2(1.0f);
  // v runs down the image (glTF convention): the edge_v side is the texture's top row.
  mesh.uvs = {{0.0f, extent.y}, extent, {extent.x, 0.0f}, {0.0f, 0.0f}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

Mesh make_quad(vec2 size, float uv_tile) {
  // Edge u along +X and edge v along -Z: cross(u, v) is +Y.
  return make_quad_corners(vec3(-0.5f * size.x, 0.0f, 0.5f * size.y), vec3(size.x, 0.0f, 0.0f),
                           vec3(0.0f, 0.0f, -size.y), uv_tile);
}

std::array<Mesh, 6> make_box_faces(vec3 lo, vec3 hi, float uv_tile) {
  const vec3 d = hi - lo;
  const vec3 x(d.x, 0, 0), y(0, d.y, 0), z(0, 0, d.z);
  // Each face seen from outside: u to the right, v up (walls) so textures stand upright.
  return {
      make_quad_corners(lo, z, y, uv_tile),                       // -X
      make_quad_corners(vec3(hi.x, lo.y, hi.z), -z, y, uv_tile),  // +X
      make_quad_corners(lo, x, z, uv_tile),                       // -Y
      make_quad_corners(vec3(lo.x, hi.y, hi.z), x, -z, uv_tile),  // +Y
      make_quad_corners(vec3(hi.x, lo.y, lo.z), -x, y, uv_tile),  // -Z
      make_quad_corners(vec3(lo.x, lo.y, hi.z), x, y, uv_tile),   // +Z
  };
}

Mesh make_box(vec3 lo, vec3 hi, float uv_tile) {
  Mesh box;
  for (const Mesh& face : make_box_faces(lo, hi, uv_tile)) append_mesh(box, face);
  return box;
}

Mesh make_sphere(float radius, int rings, int segments) {
  Mesh mesh;
  add_grid(mesh, rings, segments, [&](int i, int j) {
    // Exact poles: theta = 0 and pi give sin(theta) = 0 on every segment.
    const vec2 polar = unit_circle(i, 2 * rings);
    const float sin_theta = (i == 0 || i == rings) ? 0.0f : polar.y;
    const float cos_theta = i == 0 ? 1.0f : i == rings ? -1.0f : polar.x;
    const vec2 c = unit_circle(j, segments);
    const vec3 n(sin_theta * c.x, cos_theta, sin_theta * c.y);
    return GridVertex{radius * n, n, vec2(float(j) / float(segments), float(i) / float(rings))};
  });
  return mesh;
}

Mesh make_cylinder(float radius, float inner_radius, float height, int segments, bool caps) {
  Mesh mesh;
  const float y0 = -0.5f * height, y1 = 0.5f * height;
  add_wall(mesh, radius, y0, y1, segments, true);
  if (inner_radius > 0.0f) add_wall(mesh, inner_radius, y0, y1, segments, false);
  if (caps || inner_radius > 0.0f) {
    add_annulus(mesh, inner_radius, radius, y1, segments, true);
    add_annulus(mesh, inner_radius, radius, y0, segments, false);
  }
  return mesh;
}

Mesh make_torus(float major_radius, float minor_radius, int rings, int segments) {
  Mesh mesh;
  add_grid(mesh, rings, segments, [&](int i, int j) {
    const vec2 tube = unit_circle(i, rings);
    const vec2 c = unit_circle(j, segments);
    const vec3 n(tube.x * c.x, tube.y, tube.x * c.y);
    const vec3 centre(major_radius * c.x, 0.0f, major_radius * c.y);
    return GridVertex{centre + minor_radius * n, n,
                      vec2(float(j) / float(segments), float(i) / float(rings))};
  });
  return mesh;
}

std::vector<vec2> thick_profile(const std::vector<vec2>& profile, float thickness) {
  const size_t n = profile.size();
  // Outward normal of segment k: the direction rotated clockwise, (dy, -dr).
  auto segment_normal = [&](size_t k) {
    const vec2 d = profile[k + 1] - profile[k];
    const float length = glm::length(d);
    return length > 0.0f ? vec2(d.y, -d.x) / length : vec2(0.0f);
  };
  std::vector<vec2> inner(n);
  for (size_t i = 0; i < n; ++i) {
    const vec2 before = i > 0 ? segment_normal(i - 1) : vec2(0.0f);
    const vec2 after = i + 1 < n ? segment_normal(i) : vec2(0.0f);
    vec2 normal = before + after;
    if (glm::length(normal) == 0.0f) normal = after + before + vec2(1.0f, 0.0f);
    normal = glm::normalize(normal);
    // Mitre so both walls keep the thickness, limited at sharp corners.
    const vec2 reference = glm::length(after) > 0.0f ? after : before;
    const float cosine = std::max(glm::dot(normal, reference), 0.33f);
    vec2 p = profile[i] - normal * (thickness / cosine);
    p.x = profile[i].x == 0.0f ? 0.0f : std::max(p.x, 0.0f);  // points on the axis stay there
    inner[i] = p;
  }
  std::vector<vec2> loop = profile;
  loop.insert(loop.end(), inner.rbegin(), inner.rend());
  return loop;
}

Mesh make_revolution(const std::vector<vec2>& input_profile, float thickness, int segments,
                     float crease_angle_deg) {
  const std::vector<vec2> profile =
      thickness > 0.0f ? thick_profile(input_profile, thickness) : input_profile;
  const size_t n = profile.size();
  std::vector<vec2> segment_normal(n - 1, vec2(0.0f));
  std::vector<float> arc(n, 0.0f);  // arc length to each point, for v
  for (size_t k = 0; k + 1 < n; ++k) {
    const vec2 d = profile[k + 1] - profile[k];
    const float length = glm::length(d);
    if (length > 0.0f) segment_normal[k] = vec2(d.y, -d.x) / length;
    arc[k + 1] = arc[k] + length;
  }
  const float total = arc[n - 1] > 0.0f ? arc[n - 1] : 1.0f;
  const float crease_cos = std::cos(glm::radians(crease_angle_deg));
  // Normal at point i as seen from segment k: averaged with the neighbour across a smooth
  // joint, the segment's own normal across a crease or at an end.
  auto joint_normal = [&](size_t i, size_t k) {
    const size_t other = i == k ? k - 1 : k + 1;  // the neighbouring segment at point i
    const bool has_other = i == k ? (k > 0) : (k + 2 < n);
    if (!has_other) return segment_normal[k];
    const vec2 m = segment_normal[other];
    if (glm::dot(m, segment_normal[k]) < crease_cos) return segment_normal[k];
    const vec2 sum = m + segment_normal[k];
    return glm::length(sum) > 0.0f ? glm::normalize(sum) : segment_normal[k];
  };
  Mesh mesh;
  for (size_t k = 0; k + 1 < n; ++k) {
    if (segment_normal[k] == vec2(0.0f)) continue;  // repeated point
    add_grid(mesh, 1, segments, [&](int row, int j) {
      const size_t i = k + size_t(row);
      const vec2 p = profile[i];
      const vec2 normal2 = joint_normal(i, k);
      const vec2 c = unit_circle(j, segments);
      return GridVertex{vec3(p.x * c.x, p.y, p.x * c.y),
                        vec3(normal2.x * c.x, normal2.y, normal2.x * c.y),
                        vec2(float(j) / float(segments), 1.0f - arc[i] / total)};
    });
  }
  weld_identical(mesh);
  return mesh;
}

void transform_mesh(Mesh& mesh, const glm::mat4& transform) {
  const glm::mat3 linear(transform);
  const glm::mat3 normal_matrix = glm::transpose(glm::inverse(linear));
  for (vec3& p : mesh.positions) p = vec3(transform * vec4(p, 1.0f));
  for (vec3& n : mesh.normals) {
    const vec3 m = normal_matrix * n;
    if (glm::length(m) > 0.0f) n = glm::normalize(m);
  }
  const bool mirrors = glm::determinant(linear) < 0.0f;
  for (vec4& t : mesh.tangents) {
    const vec3 m = linear * vec3(t);
    t = vec4(glm::length(m) > 0.0f ? glm::normalize(m) : vec3(t), mirrors ? -t.w : t.w);
  }
  if (mirrors)
    for (uvec3& t : mesh.triangles) std::swap(t.y, t.z);
}

void flip_mesh(Mesh& mesh) {
  for (uvec3& t : mesh.triangles) std::swap(t.y, t.z);
  for (vec3& n : mesh.normals) n = -n;
  for (vec4& t : mesh.tangents) t.w = -t.w;
}

void append_mesh(Mesh& dst, const Mesh& src) {
  const bool first = dst.positions.empty();
  const uint32_t base = uint32_t(dst.positions.size());
  auto append_attribute = [&](auto& to, const auto& from) {
    if (first || (!to.empty() && !from.empty()))
      to.insert(to.end(), from.begin(), from.end());
    else
      to.clear();  // one side lacks it: drop it rather than leave it short
  };
  dst.positions.insert(dst.positions.end(), src.positions.begin(), src.positions.end());
  append_attribute(dst.normals, src.normals);
  append_attribute(dst.uvs, src.uvs);
  append_attribute(dst.lightmap_uvs, src.lightmap_uvs);
  append_attribute(dst.tangents, src.tangents);
  for (uvec3 t : src.triangles) dst.triangles.push_back(t + uvec3(base));
}

void compute_normals(Mesh& mesh, float crease_angle_deg) {
  const size_t vertex_count = mesh.positions.size();
  std::vector<vec3> face_cross(mesh.triangles.size());
  std::vector<std::vector<uint32_t>> faces_of(vertex_count);
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    const uvec3 t = mesh.triangles[f];
    const vec3 a = mesh.positions[t.x];
    face_cross[f] = glm::cross(mesh.positions[t.y] - a, mesh.positions[t.z] - a);
    for (int k = 0; k < 3; ++k) faces_of[t[k]].push_back(uint32_t(f));
  }
  auto unit = [](vec3 v) { return glm::length(v) > 0.0f ? glm::normalize(v) : vec3(0.0f); };
  const float crease_cos = std::cos(glm::radians(crease_angle_deg));
  // One output vertex per (input vertex, smoothing group); groups matched by their normal.
  std::vector<std::vector<std::pair<vec3, uint32_t>>> split(vertex_count);
  Mesh out;
  out.name = mesh.name;
  out.material = mesh.material;
  out.bake = mesh.bake;
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    const vec3 own = unit(face_cross[f]);
    uvec3 corners;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = mesh.triangles[f][k];
      vec3 sum(0.0f);
      for (uint32_t g : faces_of[v])
        if (glm::dot(unit(face_cross[g]), own) >= crease_cos) sum += face_cross[g];
      vec3 normal = unit(sum);
      if (normal == vec3(0.0f)) normal = own == vec3(0.0f) ? vec3(0, 0, 1) : own;
      uint32_t index = UINT32_MAX;
      for (const auto& [n, i] : split[v])
        if (glm::dot(n, normal) > 0.99999f) index = i;
      if (index == UINT32_MAX) {
        index = uint32_t(out.positions.size());
        split[v].push_back({normal, index});
        out.positions.push_back(mesh.positions[v]);
        out.normals.push_back(normal);
        if (!mesh.uvs.empty()) out.uvs.push_back(mesh.uvs[v]);
        if (!mesh.lightmap_uvs.empty()) out.lightmap_uvs.push_back(mesh.lightmap_uvs[v]);
      }
      corners[k] = index;
    }
    out.triangles.push_back(corners);
  }
  mesh = std::move(out);
}

void compute_tangents(Mesh& mesh) {
  const size_t count = mesh.positions.size();
  std::vector<vec3> tangent(count, vec3(0.0f)), bitangent(count, vec3(0.0f));
  if (mesh.uvs.size() == count) {
    for (uvec3 t : mesh.triangles) {
      const vec3 e1 = mesh.positions[t.y] - mesh.positions[t.x];
      const vec3 e2 = mesh.positions[t.z] - mesh.positions[t.x];
      const vec2 d1 = mesh.uvs[t.y] - mesh.uvs[t.x];
      const vec2 d2 = mesh.uvs[t.z] - mesh.uvs[t.x];
      const float det = d1.x * d2.y - d2.x * d1.y;
      if (std::abs(det) < 1e-20f) continue;
      const vec3 dp_du = (e1 * d2.y - e2 * d1.y) / det;
      const vec3 dp_dv = (e2 * d1.x - e1 * d2.x) / det;
      for (int k = 0; k < 3; ++k) {
        tangent[t[k]] += dp_du;
        bitangent[t[k]] += dp_dv;
      }
    }
  }
  mesh.tangents.resize(count);
  for (size_t v = 0; v < count; ++v) {
    const vec3 n = v < mesh.normals.size() ? mesh.normals[v] : vec3(0, 0, 1);
    vec3 t = tangent[v] - n * glm::dot(n, tangent[v]);
    if (glm::length(t) < 1e-12f) {
      // No usable UV gradient: any direction in the tangent plane.
      t = std::abs(n.x) < 0.9f ? vec3(1, 0, 0) : vec3(0, 1, 0);
      t -= n * glm::dot(n, t);
    }
    t = glm::normalize(t);
    const float handedness = glm::dot(glm::cross(n, t), bitangent[v]) < 0.0f ? -1.0f : 1.0f;
    mesh.tangents[v] = vec4(t, handedness);
  }
}

}  // namespace lb
