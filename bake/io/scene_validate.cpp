// validate_scene: the invariants every pass relies on, checked once after either loader.
// Fatal problems throw SceneError naming the file and the mesh/material; fixable ones
// (degenerate triangles, non-unit normals) are fixed and counted in one warning per mesh.

#include "bake/io/scene_validate.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <tuple>

#include "bake/io/input_limits.h"

namespace lb {

namespace {

bool finite(vec3 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
bool finite(vec2 v) {
  return std::isfinite(v.x) && std::isfinite(v.y);
}
bool finite(vec4 v) {
  return finite(vec3(v)) && std::isfinite(v.w);
}

std::string format_vec3(vec3 v) {
  std::ostringstream out;
  out << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return out.str();
}

class Validator {
 public:
  Validator(Scene& scene, std::vector<std::string>& warnings,
            const std::vector<std::string>& mesh_places, bool whole_scene)
      : scene_(scene),
        warnings_(warnings),
        mesh_places_(mesh_places),
        file_(scene.source_path),
        whole_scene_(whole_scene) {}

  void run() {
    for (size_t i = 0; i < scene_.textures.size(); ++i) check_texture(i);
    for (size_t i = 0; i < scene_.materials.size(); ++i) check_material(i);
    for (size_t i = 0; i < scene_.meshes.size(); ++i) check_mesh(i);
    for (size_t i = 0; i < scene_.cameras.size(); ++i) check_camera(i);
    for (size_t i = 0; i < scene_.lights.size(); ++i) check_lamp(i);
    if (scene_.sky) check_sky();
    bool any_light = !scene_.lights.empty() || (scene_.sky && scene_.sky->radiance != vec3(0.0f));
    for (const Mesh& mesh : scene_.meshes)
      any_light = any_light || scene_.materials[size_t(mesh.material)].is_emitter();
    if (!any_light && whole_scene_)
      warnings_.push_back(
          file_ +
          ": nothing emits light (no lamp, no sky, no material with emission or power); "
          "the scene will render black");
  }

 private:
  [[noreturn]] void fail(const std::string& place, const std::string& message) const {
    throw SceneError(file_ + ": " + place + ": " + message);
  }

  std::string material_place(size_t i) const {
    return "material '" + scene_.materials[i].name + "' (materials[" + std::to_string(i) + "])";
  }
  // "FILE: mesh 'NAME' (meshes[i])", or the loader's place for it when it gave one.
  std::string mesh_prefix(size_t i) const {
    if (i < mesh_places_.size()) return mesh_places_[i] + ": mesh '" + scene_.meshes[i].name + "'";
    return file_ + ": mesh '" + scene_.meshes[i].name + "' (meshes[" + std::to_string(i) + "])";
  }
  [[noreturn]] void fail_mesh(size_t i, const std::string& message) const {
    throw SceneError(mesh_prefix(i) + ": " + message);
  }

  void check_texture(size_t i) {
    const Texture& t = scene_.textures[i];
    const std::string place = "texture '" + t.path + "' (textures[" + std::to_string(i) + "])";
    if (t.width <= 0 || t.height <= 0 || t.channels < 1 || t.channels > 4 ||
        t.texels.size() != size_t(t.width) * size_t(t.height) * size_t(t.channels))
      fail(place, "size does not match its texel data");
  }

  void check_texture_index(size_t material, int texture, const char* what) {
    if (texture < -1 || texture >= int(scene_.textures.size()))
      fail(material_place(material), std::string(what) + " index " + std::to_string(texture) +
                                         " out of range (" +
                                         std::to_string(scene_.textures.size()) + " textures)");
  }

  void check_material(size_t i) {
    const Material& m = scene_.materials[i];
    const std::string place = material_place(i);
    const vec3 r = m.reflectance;
    if (!finite(r) || glm::any(glm::lessThan(r, vec3(0.0f))) ||
        glm::any(glm::greaterThan(r, vec3(1.0f))))
      fail(place, "reflectance " + format_vec3(r) + " is outside [0, 1]");
    if (!finite(m.emission) || glm::any(glm::lessThan(m.emission, vec3(0.0f))))
      fail(place, "emitted radiance " + format_vec3(m.emission) +
                      " W/(sr m^2) must be finite and not negative");
    if (m.kind == MaterialKind::glass && !(m.ior >= 1.0f && std::isfinite(m.ior)))
      fail(place, "index of refraction " + std::to_string(m.ior) + " is below 1");
    if (m.kind == MaterialKind::glossy && !(m.roughness > 0.0f && m.roughness <= 1.0f))
      fail(place, "glossy roughness " + std::to_string(m.roughness) + " is outside (0, 1]");
    if (!std::isfinite(m.bump_scale)) fail(place, "bump scale is not finite");
    check_texture_index(i, m.reflectance_texture, "reflectance texture");
    check_texture_index(i, m.bump_texture, "bump texture");
    if (m.bump != BumpKind::none && m.bump_texture < 0) fail(place, "bump without a texture");
  }

  void check_camera(size_t i) {
    const Camera& c = scene_.cameras[i];
    const std::string place = "camera '" + c.name + "' (cameras[" + std::to_string(i) + "])";
    if (!finite(c.position) || !finite(c.target) || !finite(c.up))
      fail(place, "position, target and up must be finite");
    if (glm::length(c.target - c.position) <= 0.0f) fail(place, "target equals position");
    if (glm::length(glm::cross(c.target - c.position, c.up)) <= 0.0f)
      fail(place, "up is parallel to the viewing direction");
    if (!(c.vertical_fov_deg > 0.0f && c.vertical_fov_deg < 180.0f))
      fail(place, "field of view must be in (0, 180) degrees");
    if (!(c.aperture_radius >= 0.0f) || !(c.focus_distance >= 0.0f))
      fail(place, "aperture and focus distance must not be negative");
  }

  // Lamps as every pass expects them: finite, unit directions, cones inside a hemisphere.
  void check_lamp(size_t i) {
    Lamp& lamp = scene_.lights[i];
    const std::string place = "light '" + lamp.name + "' (lights[" + std::to_string(i) + "])";
    if (!finite(lamp.position)) fail(place, "position is not finite");
    if (!finite(lamp.intensity) || glm::any(glm::lessThan(lamp.intensity, vec3(0.0f))))
      fail(place, "intensity " + format_vec3(lamp.intensity) + " must be finite and not negative");
    const float length = glm::length(lamp.direction);
    if (!(length > 0.0f) || !std::isfinite(length))
      fail(place, "direction must be finite and non-zero");
    lamp.direction /= length;
    if (!(lamp.range >= 0.0f) || !std::isfinite(lamp.range))
      fail(place, "range must be finite and not negative (0: unlimited)");
    // inner == outer is a hard-edged cone (Blender's blend 0; spot_falloff's floor).
    if (lamp.kind == LampKind::spot &&
        !(lamp.inner_cone >= 0.0f && lamp.inner_cone <= lamp.outer_cone &&
          lamp.outer_cone > 0.0f && lamp.outer_cone <= 1.5707964f))
      fail(place, "spot cone angles need 0 <= inner <= outer <= pi/2 radians, got inner " +
                      std::to_string(lamp.inner_cone) + " and outer " +
                      std::to_string(lamp.outer_cone));
  }

  void check_sky() {
    const Sky& sky = *scene_.sky;
    if (!finite(sky.radiance) || glm::any(glm::lessThan(sky.radiance, vec3(0.0f))))
      fail("sky",
           "radiance " + format_vec3(sky.radiance) + " W/(sr m^2) must be finite and not negative");
    if (sky.texture < -1 || sky.texture >= int(scene_.textures.size()))
      fail("sky", "texture index " + std::to_string(sky.texture) + " out of range");
  }

  template <class Attribute>
  void check_attribute(size_t i, const std::vector<Attribute>& values, const char* what) {
    const Mesh& mesh = scene_.meshes[i];
    if (!values.empty() && values.size() != mesh.positions.size())
      fail_mesh(i, std::string(what) + " has " + std::to_string(values.size()) + " entries for " +
                       std::to_string(mesh.positions.size()) + " vertices");
    for (size_t v = 0; v < values.size(); ++v)
      if (!finite(values[v]))
        fail_mesh(i, std::string(what) + " of vertex " + std::to_string(v) + " is NaN or infinite");
  }

  void check_mesh(size_t i) {
    Mesh& mesh = scene_.meshes[i];
    if (mesh.material < 0 || mesh.material >= int(scene_.materials.size()))
      fail_mesh(i, "material index " + std::to_string(mesh.material) + " out of range (" +
                       std::to_string(scene_.materials.size()) + " materials)");
    if (mesh.positions.empty() || mesh.triangles.empty())
      fail_mesh(i, "empty mesh (" + std::to_string(mesh.positions.size()) + " vertices, " +
                       std::to_string(mesh.triangles.size()) + " triangles)");
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      const vec3 p = mesh.positions[v];
      if (!finite(p))
        fail_mesh(i, "vertex " + std::to_string(v) + " has a NaN or infinite coordinate " +
                         format_vec3(p));
      // Areas (products of two coordinates) would overflow float; see input_limits.h.
      if (std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) > limits::kMaxCoordinate)
        fail_mesh(i, "vertex " + std::to_string(v) + " coordinate " + format_vec3(p) +
                         " is out of range (|x| above 1e18 m overflows areas)");
    }
    check_attribute(i, mesh.normals, "normals");
    check_attribute(i, mesh.uvs, "uvs");
    check_attribute(i, mesh.lightmap_uvs, "lightmap_uvs");
    check_attribute(i, mesh.tangents, "tangents");
    const uint32_t vertex_count = uint32_t(mesh.positions.size());
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
      const uvec3 tri = mesh.triangles[t];
      if (tri.x >= vertex_count || tri.y >= vertex_count || tri.z >= vertex_count)
        fail_mesh(i, "triangle " + std::to_string(t) + " has a vertex index out of range (" +
                         std::to_string(tri.x) + ", " + std::to_string(tri.y) + ", " +
                         std::to_string(tri.z) + "; " + std::to_string(vertex_count) +
                         " vertices)");
    }
    drop_degenerate_triangles(i);
    fix_normals(i);
    warn_non_manifold(i);
  }

  void drop_degenerate_triangles(size_t i) {
    Mesh& mesh = scene_.meshes[i];
    std::vector<uvec3> kept;
    kept.reserve(mesh.triangles.size());
    size_t repeated = 0, zero_area = 0;
    for (uvec3 t : mesh.triangles) {
      if (t.x == t.y || t.y == t.z || t.z == t.x) {
        ++repeated;
        continue;
      }
      if (zero_area_triangle(mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z])) {
        ++zero_area;
        continue;
      }
      kept.push_back(t);
    }
    if (repeated + zero_area == 0) return;
    if (kept.empty())
      fail_mesh(i, "empty mesh: all " + std::to_string(mesh.triangles.size()) +
                       " triangles are degenerate or have zero area");
    warnings_.push_back(mesh_prefix(i) + ": dropped " + std::to_string(repeated + zero_area) +
                        " of " + std::to_string(mesh.triangles.size()) + " triangles (" +
                        std::to_string(repeated) + " degenerate, " + std::to_string(zero_area) +
                        " zero-area)");
    mesh.triangles = std::move(kept);
  }

  // Non-unit normals are normalised; zero ones take the mean of their triangles' normals.
  void fix_normals(size_t i) {
    Mesh& mesh = scene_.meshes[i];
    if (mesh.normals.empty()) return;
    std::vector<vec3> face_sum(mesh.positions.size(), vec3(0.0f));
    bool any_zero = false;
    for (const vec3& n : mesh.normals) any_zero = any_zero || glm::length(n) < 1e-20f;
    if (any_zero)
      for (size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k)
          face_sum[mesh.triangles[t][k]] += triangle_normal(mesh, t) * triangle_area(mesh, t);
    size_t replaced = 0;
    for (size_t v = 0; v < mesh.normals.size(); ++v) {
      vec3& n = mesh.normals[v];
      const float length = glm::length(n);
      if (length >= 1e-20f) {
        n /= length;
      } else {
        ++replaced;
        n = glm::length(face_sum[v]) > 0.0f ? glm::normalize(face_sum[v]) : vec3(0, 0, 1);
      }
    }
    if (replaced > 0)
      warnings_.push_back(mesh_prefix(i) + ": " + std::to_string(replaced) +
                          " zero-length normals replaced by the faces' normals");
  }

  // An edge (between welded positions) used by more than two triangles is non-manifold:
  // kept as is, but radiosity patches and charts may look odd there.
  void warn_non_manifold(size_t i) {
    const Mesh& mesh = scene_.meshes[i];
    std::map<std::tuple<float, float, float>, uint32_t> position_id;
    std::vector<uint32_t> welded(mesh.positions.size());
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      const vec3 p = mesh.positions[v];
      welded[v] =
          position_id.try_emplace({p.x, p.y, p.z}, uint32_t(position_id.size())).first->second;
    }
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> uses;
    for (uvec3 t : mesh.triangles)
      for (int k = 0; k < 3; ++k) {
        uint32_t a = welded[t[k]], b = welded[t[(k + 1) % 3]];
        if (a > b) std::swap(a, b);
        ++uses[{a, b}];
      }
    size_t non_manifold = 0;
    for (const auto& [edge, count] : uses) non_manifold += count > 2 ? 1 : 0;
    if (non_manifold > 0)
      warnings_.push_back(mesh_prefix(i) + ": non-manifold: " + std::to_string(non_manifold) +
                          " edge(s) shared by more than two triangles (kept)");
  }

  Scene& scene_;
  std::vector<std::string>& warnings_;
  const std::vector<std::string>& mesh_places_;
  std::string file_;
  bool whole_scene_;
};

}  // namespace

void validate_scene(Scene& scene, std::vector<std::string>& warnings) {
  validate_scene(scene, warnings, {});
}

void validate_scene(Scene& scene, std::vector<std::string>& warnings,
                    const std::vector<std::string>& mesh_places, bool whole_scene) {
  Validator(scene, warnings, mesh_places, whole_scene).run();
}

}  // namespace lb
