#include "bake/pipeline/bake_io.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "bake/io/atomic_file.h"
#include "bake/io/image_io.h"
#include "bake/input_file.h"
#include "bake/json_text.h"
#include "bake/light_groups.h"
#include "bake/pipeline/bake_settings.h"
#include "bake/binary_file.h"
#include "bake/quality.h"
#include "bake/work_limits.h"

using nlohmann::json;

// The manifest's JSON: vectors as [x, y, z]; stats and settings field by field, so a field
// added to a struct is one name added here.
template <>
struct nlohmann::adl_serializer<glm::vec3> {
  static void to_json(json& j, const glm::vec3& v) { j = json::array({v.x, v.y, v.z}); }
  static void from_json(const json& j, glm::vec3& v) {
    v = {j.at(0).get<float>(), j.at(1).get<float>(), j.at(2).get<float>()};
  }
};

namespace lb {

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(IlluminationStats, feeler_rays, illumination_rays,
                                                ray_casts, zones_total, zones_traced, power_sent,
                                                power_deposited, power_absorbed, power_escaped,
                                                power_direct, seconds, feeler_seconds, emitter_hits,
                                                rays_saved, atlas_seconds, pilot_rays,
                                                pilot_deposits, pilot_seconds, pilot_texel_size,
                                                pilot_peak_density)
// With defaults: a bake written before a field existed still loads.
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(RadiosityStats, shots, rays, light_rays, ray_casts,
                                                patch_count, power_emitted, residual_unsent,
                                                residual_fraction, converged, power_absorbed,
                                                power_escaped, power_received, seconds,
                                                setup_seconds)

namespace {

constexpr int kFormatVersion = 7;  // 2: illumination.bin carries vertex splits; 3: the atlas
                                   // covers every diffuse mesh and records texel sizes; 4: the
                                   // soft-light texel map (soft_light.exr); 5: checksums (.bin
                                   // trailers, the manifest's "checksums"); 6: the caustic
                                   // map's L1 band (illumination_l1{x,y,z}.exr), optional; 7:
                                   // the soft map's (soft_light_l1{x,y,z}.exr), optional
// A version-5 bake reads as one without bands, a version-6 one without the soft map's band.
constexpr int kOldestReadVersion = 5;

// The caustic map's L1 band, one RGB EXR per world axis (IlluminationMaps::l1), and the
// manifest's "files" keys naming them.
constexpr const char* kL1Files[3] = {"illumination_l1x.exr", "illumination_l1y.exr",
                                     "illumination_l1z.exr"};
constexpr const char* kL1Keys[3] = {"illumination_l1x_exr", "illumination_l1y_exr",
                                    "illumination_l1z_exr"};
// The soft-light map's L1 band (SoftTexelMap::l1), the same way.
constexpr const char* kSoftL1Files[3] = {"soft_light_l1x.exr", "soft_light_l1y.exr",
                                         "soft_light_l1z.exr"};
constexpr const char* kSoftL1Keys[3] = {"soft_light_l1x_exr", "soft_light_l1y_exr",
                                        "soft_light_l1z_exr"};

// ---- the two binary files ------------------------------------------------------------------

// The file's content; save() appends its checksum.
Writer encode_illumination(const IlluminationMaps& maps) {
  Writer w;
  w.put_bytes("LBILLUM4");
  w.put(uint32_t(maps.width));
  w.put(uint32_t(maps.height));
  w.put(maps.texel_size);
  const size_t texels = size_t(maps.width) * size_t(maps.height);
  if (maps.texel_area.size() != texels || maps.valid.size() != texels)
    throw std::runtime_error("illumination maps: texel arrays do not match the atlas size");
  w.put_array(maps.texel_area);
  w.put_array(maps.valid);
  w.put(uint32_t(maps.lightmap_uvs.size()));
  for (size_t m = 0; m < maps.lightmap_uvs.size(); ++m) {
    const std::vector<vec2>& uvs = maps.lightmap_uvs[m];
    const VertexSplit none;
    const VertexSplit& split = m < maps.vertex_splits.size() ? maps.vertex_splits[m] : none;
    w.put(uint32_t(uvs.size()));
    w.put_array(uvs);
    w.put(uint32_t(split.copied_from.size()));
    w.put_array(split.copied_from);
    w.put(uint32_t(split.triangles.size()));
    w.put_array(split.triangles);
    w.put(m < maps.mesh_texel_size.size() ? maps.mesh_texel_size[m] : 0.0f);
  }
  return w;
}

// Returns the file's checksum (checked against its content before anything is parsed).
uint64_t decode_illumination(const std::string& path, const Scene& scene, IlluminationMaps& maps) {
  Reader r(path);
  const uint64_t checksum = r.check_checksum();
  r.expect_magic("LBILLUM4");
  maps.width = int(r.get<uint32_t>());
  maps.height = int(r.get<uint32_t>());
  maps.texel_size = r.get<float>();
  const size_t texels = size_t(maps.width) * size_t(maps.height);
  maps.texel_area = r.get_array<float>(texels);
  maps.valid = r.get_array<uint8_t>(texels);
  const size_t mesh_count = r.get<uint32_t>();
  if (mesh_count != scene.meshes.size())
    r.fail(std::to_string(mesh_count) + " meshes, the scene has " +
           std::to_string(scene.meshes.size()));
  maps.lightmap_uvs.resize(mesh_count);
  maps.vertex_splits.resize(mesh_count);
  maps.mesh_texel_size.resize(mesh_count);
  for (size_t m = 0; m < mesh_count; ++m) {
    const Mesh& mesh = scene.meshes[m];
    maps.lightmap_uvs[m] = r.get_array<vec2>(r.get<uint32_t>());
    VertexSplit& split = maps.vertex_splits[m];
    split.copied_from = r.get_array<uint32_t>(r.get<uint32_t>());
    split.triangles = r.get_array<uvec3>(r.get<uint32_t>());
    // A split must fit the scene mesh it claims to split, or split_vertices would read
    // out of bounds.
    const size_t vertices = mesh.positions.size() + split.copied_from.size();
    bool fits = split.triangles.empty() ? split.copied_from.empty()
                                        : split.triangles.size() == mesh.triangles.size();
    for (uint32_t v : split.copied_from) fits = fits && v < mesh.positions.size();
    for (const uvec3& t : split.triangles)
      fits = fits && t.x < vertices && t.y < vertices && t.z < vertices;
    if (!maps.lightmap_uvs[m].empty()) fits = fits && maps.lightmap_uvs[m].size() == vertices;
    maps.mesh_texel_size[m] = r.get<float>();
    fits = fits && std::isfinite(maps.mesh_texel_size[m]) && maps.mesh_texel_size[m] >= 0.0f;
    if (!fits)
      r.fail("the lightmap layout of mesh " + std::to_string(m) + " ('" + mesh.name +
             "') does not fit the scene's mesh");
  }
  r.expect_end();
  return checksum;
}

constexpr uint32_t kNormals = 1, kUvs = 2, kLightmapUvs = 4, kTangents = 8;  // attribute flags

Writer encode_radiosity(const VertexRadiosity& radiosity) {
  Writer w;
  w.put_bytes("LBRADIO2");
  w.put(uint32_t(radiosity.meshes.size()));
  for (const MeshRadiosity& r : radiosity.meshes) {
    const Mesh& mesh = r.mesh;
    const size_t v = mesh.positions.size();
    w.put(uint32_t(v));
    if (v == 0) continue;
    auto has = [&](const auto& a) { return a.size() == v; };
    if (r.vertex_radiance.size() != v || r.triangle_patch.size() != mesh.triangles.size())
      throw std::runtime_error("radiosity mesh '" + mesh.name + "': arrays do not match");
    const uint32_t flags = (has(mesh.normals) ? kNormals : 0) | (has(mesh.uvs) ? kUvs : 0) |
                           (has(mesh.lightmap_uvs) ? kLightmapUvs : 0) |
                           (has(mesh.tangents) ? kTangents : 0);
    w.put(uint32_t(mesh.triangles.size()));
    w.put(flags);
    w.put(int32_t(mesh.material));
    w.put(uint32_t(mesh.name.size()));
    w.put_bytes(mesh.name);
    w.put_array(mesh.positions);
    if (flags & kNormals) w.put_array(mesh.normals);
    if (flags & kUvs) w.put_array(mesh.uvs);
    if (flags & kLightmapUvs) w.put_array(mesh.lightmap_uvs);
    if (flags & kTangents) w.put_array(mesh.tangents);
    w.put_array(mesh.triangles);
    w.put_array(r.vertex_radiance);
    w.put_array(r.triangle_patch);
  }
  return w;
}

uint64_t decode_radiosity(const std::string& path, const Scene& scene,
                          VertexRadiosity& radiosity) {
  Reader r(path);
  const uint64_t checksum = r.check_checksum();
  r.expect_magic("LBRADIO2");
  // Checked before anything is sized by it: a corrupt count would ask for terabytes.
  const size_t mesh_count = r.get<uint32_t>();
  if (mesh_count != scene.meshes.size())
    r.fail(std::to_string(mesh_count) + " meshes, the scene has " +
           std::to_string(scene.meshes.size()));
  radiosity.meshes.resize(mesh_count);
  for (size_t m = 0; m < radiosity.meshes.size(); ++m) {
    MeshRadiosity& out = radiosity.meshes[m];
    const uint32_t v = r.get<uint32_t>();
    if (v == 0) continue;
    Mesh& mesh = out.mesh;
    const uint32_t t = r.get<uint32_t>();
    const uint32_t flags = r.get<uint32_t>();
    mesh.material = r.get<int32_t>();
    if (mesh.material < 0 || size_t(mesh.material) >= scene.materials.size())
      r.fail("material index out of range");
    mesh.name = r.get_string(r.get<uint32_t>());
    if (m < scene.meshes.size()) mesh.bake = scene.meshes[m].bake;
    mesh.positions = r.get_array<vec3>(v);
    if (flags & kNormals) mesh.normals = r.get_array<vec3>(v);
    if (flags & kUvs) mesh.uvs = r.get_array<vec2>(v);
    if (flags & kLightmapUvs) mesh.lightmap_uvs = r.get_array<vec2>(v);
    if (flags & kTangents) mesh.tangents = r.get_array<vec4>(v);
    mesh.triangles = r.get_array<uvec3>(t);
    for (const uvec3& tri : mesh.triangles)
      if (tri.x >= v || tri.y >= v || tri.z >= v) r.fail("triangle index out of range");
    out.vertex_radiance = r.get_array<vec3>(v);
    out.triangle_patch = r.get_array<uint32_t>(t);
  }
  r.expect_end();
  return checksum;
}

// A light group's vertex radiance (bake_result.h, VertexRadiosity::group_vertex_radiance), over
// the vertices of radiosity.bin's meshes: "LBGROUP1", u32 mesh_count, then per mesh u32 n,
// f32 vertex_radiance[3n].
Writer encode_group_radiosity(const std::vector<std::vector<vec3>>& meshes) {
  Writer w;
  w.put_bytes("LBGROUP1");
  w.put(uint32_t(meshes.size()));
  for (const std::vector<vec3>& radiance : meshes) {
    w.put(uint32_t(radiance.size()));
    w.put_array(radiance);
  }
  return w;
}

uint64_t decode_group_radiosity(const std::string& path, const VertexRadiosity& radiosity,
                                std::vector<std::vector<vec3>>& meshes) {
  Reader r(path);
  const uint64_t checksum = r.check_checksum();
  r.expect_magic("LBGROUP1");
  const size_t mesh_count = r.get<uint32_t>();
  if (mesh_count != radiosity.meshes.size())
    r.fail(std::to_string(mesh_count) + " meshes, radiosity.bin has " +
           std::to_string(radiosity.meshes.size()));
  meshes.resize(mesh_count);
  for (size_t m = 0; m < mesh_count; ++m) {
    const size_t n = r.get<uint32_t>();
    if (n != radiosity.meshes[m].vertex_radiance.size())
      r.fail("mesh " + std::to_string(m) + " has " + std::to_string(n) +
             " vertices, radiosity.bin's " +
             std::to_string(radiosity.meshes[m].vertex_radiance.size()));
    meshes[m] = r.get_array<vec3>(n);
  }
  r.expect_end();
  return checksum;
}

// The files of light group g (0-based): groupG_illumination.exr, groupG_soft_light.exr and
// groupG_radiosity.bin, G counted from 1.
std::string group_file(size_t g, const char* what) {
  return "group" + std::to_string(g + 1) + "_" + what;
}

// Whether `name` is one of the files a bake writes per light group.
bool is_group_file(const std::string& name) {
  if (name.rfind("group", 0) != 0) return false;
  size_t k = 5;
  while (k < name.size() && std::isdigit(static_cast<unsigned char>(name[k]))) ++k;
  if (k == 5) return false;
  const std::string rest = name.substr(k);
  return rest == "_illumination.exr" || rest == "_soft_light.exr" || rest == "_radiosity.bin";
}

json read_manifest(const std::string& path) {
  if (const std::string problem = input_file_problem(path); !problem.empty())
    throw std::runtime_error(path + ": cannot open: " + problem + " (not a bake directory?)");
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open (not a bake directory?)");
  try {
    return json::parse(in);
  } catch (const json::exception& e) {  // syntax, and numbers out of range ("1E10125732")
    throw std::runtime_error(path + ": " + e.what());
  }
}

std::string join(const std::string& directory, const char* name) {
  return (std::filesystem::path(directory) / name).string();
}

bool is_empty_folder(const std::string& directory) {
  std::error_code ec;
  return std::filesystem::is_empty(directory, ec) && !ec;
}

constexpr const char* kBakeFiles[] = {
    "manifest.json",        "illumination.exr",     "illumination.bin",    "radiosity.bin",
    "soft_light.exr",       "illumination_l1x.exr", "illumination_l1y.exr",
    "illumination_l1z.exr", "soft_light_l1x.exr",   "soft_light_l1y.exr",  "soft_light_l1z.exr"};

// An atlas-sized RGB map as a float32 EXR; returns the FNV-1a of the file written.
uint64_t write_atlas_exr(const std::string& path, int width, int height,
                         const std::vector<vec3>& texels) {
  if (texels.size() != size_t(width) * size_t(height))
    throw std::runtime_error(path + ": the map does not match the atlas size");
  Image image(width, height, 3);
  std::memcpy(image.pixels.data(), texels.data(), texels.size() * sizeof(vec3));
  write_exr(path, image, ExrPixelType::float32);
  return fnv1a(Reader(path).bytes());
}

// The bake's checksums: the manifest records each file's ("checksums": {NAME: 16 hex digits}),
// the FNV-1a of an .exr's bytes and the trailing checksum of a .bin, so a file damaged or
// taken from another bake is refused.
void check_recorded_checksum(const json& checksums, const std::string& directory,
                             const char* name, uint64_t checksum,
                             const std::string& manifest_path) {
  const json recorded = checksums.value(name, json());
  if (recorded == hex_digits(checksum)) return;
  throw std::runtime_error(join(directory, name) + ": checksum " + hex_digits(checksum) +
                           " is not the " + recorded.dump() + " that " + manifest_path +
                           " records: the file is damaged or from another bake; rebake");
}

// The map is decoded from the very bytes whose checksum was checked.
std::vector<vec3> read_atlas_exr(const std::string& directory, const char* name, int width,
                                 int height, const json& checksums,
                                 const std::string& manifest_path) {
  const std::string exr = join(directory, name);
  const Reader file(exr);
  check_recorded_checksum(checksums, directory, name, fnv1a(file.bytes()), manifest_path);
  const Image image = read_image(exr, file.bytes());
  if (image.width != width || image.height != height || image.channels < 3)
    throw std::runtime_error(exr + ": expected " + std::to_string(width) + "x" +
                             std::to_string(height) + " RGB, found " + std::to_string(image.width) +
                             "x" + std::to_string(image.height) + "x" +
                             std::to_string(image.channels));
  std::vector<vec3> texels(size_t(width) * size_t(height));
  for (size_t i = 0; i < texels.size(); ++i)
    for (int c = 0; c < 3; ++c) texels[i][c] = image.pixels[i * size_t(image.channels) + size_t(c)];
  return texels;
}

// The manifest's top-level seed: a whole number, and the settings' seed where that is recorded
// (`settings_seed` null otherwise): an edited manifest whose two seeds differ is refused.
uint64_t check_recorded_seed(const json& seed, const json& settings_seed,
                             const std::string& manifest_path) {
  if (!seed.is_number_unsigned())
    throw std::runtime_error(manifest_path + ": seed: expected a whole number >= 0, got " +
                             seed.dump());
  if (!settings_seed.is_null() && settings_seed != seed)
    throw std::runtime_error(manifest_path + ": seed: " + seed.dump() +
                             " differs from settings.seed " + settings_seed.dump());
  return seed.get<uint64_t>();
}

// A "files" entry names its fixed file where the bake has one and is null where it has none:
// anything else (a null beside an atlas, another name) is an edited manifest.
void check_file_entry(const json& files, const char* key, const char* name, bool present,
                      const std::string& manifest_path) {
  const json entry = files.value(key, json());
  if (present ? entry == name : entry.is_null()) return;
  throw std::runtime_error(manifest_path + ": files." + key + ": " + entry.dump() +
                           (present ? std::string(", but the bake has '") + name + "'"
                                    : std::string(", but the bake has no such file")));
}

// The files a previous bake in `directory` wrote, which a new bake replaces: the fixed names
// this tool writes, and only where they are regular files. The manifest's own "files" list is
// not trusted for this (an edited one could name the user's files); everything else stays.
std::vector<std::string> previous_bake_files(const std::string& directory) {
  std::vector<std::string> files;
  for (const char* name : kBakeFiles) {
    std::error_code ec;
    const auto status = std::filesystem::symlink_status(join(directory, name), ec);
    if (std::filesystem::is_regular_file(status)) files.emplace_back(name);
  }
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(directory, ec)) {
    const std::string name = entry.path().filename().string();
    if (is_group_file(name) && !entry.is_symlink(ec) && entry.is_regular_file(ec))
      files.push_back(name);
  }
  return files;
}

void write_bake_files(AtomicDirectory& out, const Scene& scene, const BakeResult& bake,
                      const SaveBakeOptions& options);

// The bake's files into a temporary folder, renamed into place whole (AtomicDirectory).
void save(const std::string& directory, const Scene& scene, const BakeResult& bake,
          const SaveBakeOptions& options) {
  check_bake_destination(directory, options.force);
  AtomicDirectory out(directory, previous_bake_files(directory));
  try {
    write_bake_files(out, scene, bake, options);
  } catch (...) {
    rethrow_naming(out.temp_path(), directory);
  }
}

void write_bake_files(AtomicDirectory& out, const Scene& scene, const BakeResult& bake,
                      const SaveBakeOptions& options) {
  const BakeParams* params = options.params;
  const IlluminationMaps& maps = bake.illumination;
  const bool has_atlas = maps.width > 0 && maps.height > 0;
  json checksums = json::object();
  if (has_atlas)
    checksums["illumination.exr"] = hex_digits(
        write_atlas_exr(out.file("illumination.exr"), maps.width, maps.height, maps.radiance));
  const bool has_soft = has_atlas && !bake.soft_texels.radiance.empty();
  if (has_soft)
    checksums["soft_light.exr"] = hex_digits(write_atlas_exr(
        out.file("soft_light.exr"), maps.width, maps.height, bake.soft_texels.radiance));
  const bool has_l1 = has_atlas && maps.l1[0].size() == maps.radiance.size();
  if (has_l1)
    for (size_t a = 0; a < 3; ++a)
      checksums[kL1Files[a]] = hex_digits(
          write_atlas_exr(out.file(kL1Files[a]), maps.width, maps.height, maps.l1[a]));
  const bool has_soft_l1 = has_soft && bake.soft_texels.l1[0].size() == maps.radiance.size();
  if (has_soft_l1)
    for (size_t a = 0; a < 3; ++a)
      checksums[kSoftL1Files[a]] = hex_digits(write_atlas_exr(
          out.file(kSoftL1Files[a]), maps.width, maps.height, bake.soft_texels.l1.at(a)));
  const auto write_bin = [&](const char* name, Writer w) {
    checksums[name] = hex_digits(w.put_checksum());
    write_file_atomic(out.file(name), w.bytes());
  };
  write_bin("illumination.bin", encode_illumination(maps));
  write_bin("radiosity.bin", encode_radiosity(bake.radiosity));
  // Light groups: each group's maps and vertex radiance beside the whole light's.
  for (size_t g = 0; g < bake.light_groups.size(); ++g) {
    const std::string illumination = group_file(g, "illumination.exr"),
                      soft = group_file(g, "soft_light.exr"),
                      radiosity = group_file(g, "radiosity.bin");
    if (has_atlas)
      checksums[illumination] = hex_digits(write_atlas_exr(
          out.file(illumination), maps.width, maps.height, maps.group_radiance.at(g)));
    if (has_soft)
      checksums[soft] = hex_digits(write_atlas_exr(out.file(soft), maps.width, maps.height,
                                                   bake.soft_texels.group_radiance.at(g)));
    write_bin(radiosity.c_str(),
              encode_group_radiosity(bake.radiosity.group_vertex_radiance.at(g)));
    release_freed_memory();  // each EXR's buffers (work_limits.h)
  }

  json manifest = {
      {"format", "lightbake-bake"},
      {"version", kFormatVersion},
      {"scene", scene.source_path},
      {"scene_hash", scene_hash(scene)},
      {"mesh_count", scene.meshes.size()},
      {"seed", bake.seed},
      {"files",
       {{"illumination_exr", has_atlas ? json("illumination.exr") : json(nullptr)},
        {"illumination_bin", "illumination.bin"},
        {"radiosity_bin", "radiosity.bin"},
        {"soft_light_exr", has_soft ? json("soft_light.exr") : json(nullptr)},
        {kL1Keys[0], has_l1 ? json(kL1Files[0]) : json(nullptr)},
        {kL1Keys[1], has_l1 ? json(kL1Files[1]) : json(nullptr)},
        {kL1Keys[2], has_l1 ? json(kL1Files[2]) : json(nullptr)},
        {kSoftL1Keys[0], has_soft_l1 ? json(kSoftL1Files[0]) : json(nullptr)},
        {kSoftL1Keys[1], has_soft_l1 ? json(kSoftL1Files[1]) : json(nullptr)},
        {kSoftL1Keys[2], has_soft_l1 ? json(kSoftL1Files[2]) : json(nullptr)}}},
      {"checksums", checksums},
      {"illumination",
       {{"width", maps.width},
        {"height", maps.height},
        {"texel_density_per_m", texel_density(maps.texel_size)},
        {"rays", maps.stats.illumination_rays + maps.stats.feeler_rays},
        {"seconds", maps.stats.seconds},
        {"stats", maps.stats}}},
      {"radiosity",
       {{"rays", bake.radiosity.stats.rays + bake.radiosity.stats.light_rays},
        {"seconds", bake.radiosity.stats.seconds},
        {"patch_count", bake.radiosity.stats.patch_count},
        {"residual_fraction", bake.radiosity.stats.residual_fraction},
        {"stats", bake.radiosity.stats}}},
      {"soft_light",
       {{"gather_rays", bake.soft_texels.gather_rays},
        {"shadow_rays", bake.soft_texels.shadow_rays},
        {"distance_rays", bake.soft_texels.distance_rays},
        {"seconds", bake.soft_texels.seconds},
        {"band_rays", bake.soft_texels.band_rays},
        {"band_seconds", bake.soft_texels.band_seconds}}},
  };
  if (!bake.light_groups.empty()) manifest["light_groups"] = bake.light_groups;
  if (params) manifest["settings"] = bake_settings_json(*params);
  // What the bake held at most (the whole process so far, libraries included: ~0.2 GB of it is
  // fixed), against what it is made of; bench/scaling.py fits the cost per triangle and texel.
  manifest["memory"] = {{"peak_resident_bytes", peak_resident_bytes()},
                        {"triangles", triangle_count(scene)},
                        {"texels", uint64_t(maps.width) * uint64_t(maps.height)}};
  write_text_atomic(out.file("manifest.json"), json_text(manifest, 2) + "\n");
  out.commit();
}

}  // namespace

std::string scene_hash(const Scene& scene) {
  Fnv1a h;
  h.add(uint64_t(scene.meshes.size()));
  for (const Mesh& mesh : scene.meshes) {
    h.add(uint64_t(mesh.positions.size()));
    h.add(uint64_t(mesh.triangles.size()));
    h.add(mesh.positions.data(), mesh.positions.size() * sizeof(vec3));
    h.add(mesh.triangles.data(), mesh.triangles.size() * sizeof(uvec3));
    h.add(int32_t(mesh.material));
    h.add(mesh.bake.patch_size);
    h.add(mesh.bake.texel_size);
  }
  h.add(uint64_t(scene.materials.size()));
  for (const Material& m : scene.materials) {
    h.add(int32_t(m.kind));
    h.add(m.reflectance);
    h.add(m.emission);
    h.add(m.ior);
    h.add(m.roughness);
    h.add(int32_t(m.reflectance_texture));
    if (m.two_sided_emission) h.add(uint8_t(1));  // one-sided materials keep their hash
    if (m.two_sided_reflection) h.add(uint8_t(3));
    if (m.alpha_mask) {  // a bake from before masks were read saw the surface opaque
      h.add(uint8_t(2));
      h.add(m.alpha_cutoff);
      h.add(m.alpha_factor);
      h.add(int32_t(m.alpha_texture));
    }
    if (m.alpha_blend) {  // likewise for BLEND, read as opaque before
      h.add(uint8_t(4));
      h.add(m.alpha_factor);
      h.add(int32_t(m.alpha_texture));
    }
  }
  // Lamps and the sky, only when there are any: lamp-less scenes keep their hash, so their
  // bakes from before lamps existed still load.
  if (!scene.lights.empty() || scene.sky) {
    h.add(uint64_t(scene.lights.size()));
    for (const Lamp& lamp : scene.lights) {
      h.add(int32_t(lamp.kind));
      h.add(lamp.position);
      h.add(lamp.direction);
      h.add(lamp.intensity);
      h.add(lamp.range);
      h.add(lamp.inner_cone);
      h.add(lamp.outer_cone);
    }
    h.add(int32_t(scene.sky ? 1 : 0));
    if (scene.sky) {
      h.add(scene.sky->radiance);
      h.add(int32_t(scene.sky->texture));
    }
  }
  // Everything else the loaders read from the input files: shading attributes, bump maps and
  // every texture's texels (reflectance, bump and sky images), so a bake is refused once any
  // input file it was made from holds something else.
  const auto add_array = [&h](const auto& values) {
    h.add(uint64_t(values.size()));
    h.add(values.data(), values.size() * sizeof(values[0]));
  };
  for (const Mesh& mesh : scene.meshes) {
    add_array(mesh.normals);
    add_array(mesh.uvs);
    add_array(mesh.lightmap_uvs);
    add_array(mesh.tangents);
  }
  for (const Material& m : scene.materials) {
    h.add(int32_t(m.bump));
    h.add(int32_t(m.bump_texture));
    h.add(m.bump_scale);
  }
  // Light groups, only where the scene has any: a bake carries each group's light apart.
  if (const std::vector<std::string> groups = light_group_names(scene); !groups.empty()) {
    h.add(uint64_t(groups.size()));
    const auto add_name = [&h](const std::string& name) {
      h.add(uint64_t(name.size()));
      h.add(name.data(), name.size());
    };
    for (const std::string& g : groups) add_name(g);
    for (const Material& m : scene.materials) add_name(m.light_group);
    for (const Lamp& lamp : scene.lights) add_name(lamp.light_group);
    if (scene.sky) add_name(scene.sky->light_group);
  }
  h.add(uint64_t(scene.textures.size()));
  for (const Texture& texture : scene.textures) {
    h.add(int32_t(texture.width));
    h.add(int32_t(texture.height));
    h.add(int32_t(texture.channels));
    h.add(uint8_t(texture.srgb_decoded));
    // A sampler other than the default (read since 7 Dec 2026): a bake from before saw it bilinear
    // and repeating; default ones keep older bakes' hashes.
    if (texture.filter != TextureFilter::linear || texture.wrap_u != TextureWrap::repeat ||
        texture.wrap_v != TextureWrap::repeat) {
      h.add(uint8_t(texture.filter));
      h.add(uint8_t(texture.wrap_u));
      h.add(uint8_t(texture.wrap_v));
    }
    add_array(texture.texels);
  }
  return hex_digits(h.value());
}

std::string bake_hash(const BakeResult& bake) {
  Fnv1a h;
  const auto add_vectors = [&h](const std::vector<vec3>& v) {
    h.add(uint64_t(v.size()));
    h.add(v.data(), v.size() * sizeof(vec3));
  };
  add_vectors(bake.illumination.radiance);
  add_vectors(bake.soft_texels.radiance);
  for (const std::vector<vec3>& band : bake.illumination.l1) add_vectors(band);
  for (const std::vector<vec3>& band : bake.soft_texels.l1) add_vectors(band);
  for (const MeshRadiosity& mesh : bake.radiosity.meshes) {
    add_vectors(mesh.mesh.positions);
    add_vectors(mesh.vertex_radiance);
  }
  h.add(bake.seed);
  return hex_digits(h.value());
}

double bake_files_bytes(const Scene& scene, int atlas_width, int atlas_height, bool directional) {
  constexpr double kMapTexelBytes = 16.0, kTableTexelBytes = 8.0, kTriangleBytes = 64.0;
  constexpr double kManifestBytes = 1 << 20;
  const double lights = 1.0 + double(light_group_names(scene).size());  // the whole, each group
  const double texels = double(atlas_width) * double(atlas_height);
  return lights * (2.0 * kMapTexelBytes * texels + kTriangleBytes * double(triangle_count(scene))) +
         (directional ? 6.0 * kMapTexelBytes * texels : 0.0) + kTableTexelBytes * texels +
         kManifestBytes;
}

void save_bake(const std::string& directory, const Scene& scene, const BakeResult& bake,
               const SaveBakeOptions& options) {
  save(directory, scene, bake, options);
}

void save_bake(const std::string& directory, const Scene& scene, const BakeResult& bake,
               const BakeParams& params) {
  SaveBakeOptions options;
  options.params = &params;
  save(directory, scene, bake, options);
}

bool is_bake_directory(const std::string& directory) {
  if (!input_file_problem(join(directory, "manifest.json")).empty()) return false;
  std::ifstream in(join(directory, "manifest.json"));
  if (!in) return false;
  const json manifest = json::parse(in, nullptr, /*allow_exceptions=*/false);
  return manifest.is_object() && manifest.value("format", json()) == "lightbake-bake";
}

void check_bake_destination(const std::string& directory, bool force) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(directory, ec);
  if (!fs::exists(status)) return;
  if (!fs::is_directory(status))
    throw std::runtime_error(directory + ": exists and is not a folder; choose another name");
  // A new bake replaces its own names; one that is not a regular file is not a bake's file.
  for (const char* name : kBakeFiles) {
    const fs::file_status entry = fs::symlink_status(join(directory, name), ec);
    if (fs::exists(entry) && !fs::is_regular_file(entry))
      throw std::runtime_error(join(directory, name) +
                               ": is not a file a bake wrote (a folder, link or device); move it "
                               "out or choose another folder");
  }
  if (force || is_empty_folder(directory) || is_bake_directory(directory)) return;
  throw std::runtime_error(directory +
                           ": is a folder that holds no bake (no lightbake manifest.json); "
                           "choose a new or empty folder, or pass --force to add the bake to it "
                           "(its files are kept)");
}

BakeResult load_bake(const std::string& directory, const Scene& scene) {
  const std::string manifest_path = join(directory, "manifest.json");
  const json manifest = read_manifest(manifest_path);
  BakeResult bake;
  json files, checksums;
  try {
    if (manifest.at("format") != "lightbake-bake")
      throw std::runtime_error("not a lightbake bake manifest");
    const json& version = manifest.at("version");
    if (!version.is_number_integer() || version < kOldestReadVersion || version > kFormatVersion)
      throw std::runtime_error("format version " + version.dump() + ", this build reads " +
                               std::to_string(kOldestReadVersion) + " to " +
                               std::to_string(kFormatVersion));
    const size_t mesh_count = manifest.at("mesh_count");
    if (mesh_count != scene.meshes.size())
      throw std::runtime_error("the bake has " + std::to_string(mesh_count) +
                               " meshes, the scene " + std::to_string(scene.meshes.size()) +
                               "; rebake the scene");
    const std::string hash = manifest.at("scene_hash");
    if (hash != scene_hash(scene))
      throw std::runtime_error("the bake was made for a different scene (hash " + hash +
                               ", this scene " + scene_hash(scene) + "); rebake the scene");
    // Only the seed of the settings: a bake of an older build may hold keys gone since.
    const json settings = manifest.value("settings", json());
    const json settings_seed = settings.is_object() ? settings.value("seed", json()) : json();
    bake.seed = check_recorded_seed(manifest.at("seed"), settings_seed, manifest_path);
    const json& soft = manifest.at("soft_light");
    bake.soft_texels.gather_rays = soft.at("gather_rays");
    bake.soft_texels.shadow_rays = soft.at("shadow_rays");
    bake.soft_texels.distance_rays = soft.value("distance_rays", uint64_t(0));  // since 2 Dec 2026
    bake.soft_texels.seconds = soft.at("seconds");
    bake.soft_texels.band_rays = soft.value("band_rays", uint64_t(0));  // since version 7
    bake.soft_texels.band_seconds = soft.value("band_seconds", 0.0);
    files = manifest.at("files");
    if (!files.is_object()) throw std::runtime_error("files: expected an object");
    checksums = manifest.at("checksums");
    if (!checksums.is_object()) throw std::runtime_error("checksums: expected an object");
    manifest.at("illumination").at("stats").get_to(bake.illumination.stats);
    bake.light_groups = manifest.value("light_groups", std::vector<std::string>());
    if (bake.light_groups != light_group_names(scene))
      throw std::runtime_error("light_groups: the bake's light groups are not the scene's; "
                               "rebake the scene");
    manifest.at("radiosity").at("stats").get_to(bake.radiosity.stats);
  } catch (const json::exception& e) {
    throw std::runtime_error(manifest_path + ": " + e.what());
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).rfind(manifest_path, 0) == 0) throw;
    throw std::runtime_error(manifest_path + ": " + e.what());
  }

  IlluminationMaps& maps = bake.illumination;
  check_recorded_checksum(checksums, directory, "illumination.bin",
                          decode_illumination(join(directory, "illumination.bin"), scene, maps),
                          manifest_path);
  const size_t texels = size_t(maps.width) * size_t(maps.height);
  // Every bake with an atlas writes both maps (save above); a manifest saying otherwise would
  // have the soft light silently dropped.
  check_file_entry(files, "illumination_exr", "illumination.exr", texels > 0, manifest_path);
  check_file_entry(files, "soft_light_exr", "soft_light.exr", texels > 0, manifest_path);
  check_file_entry(files, "illumination_bin", "illumination.bin", true, manifest_path);
  check_file_entry(files, "radiosity_bin", "radiosity.bin", true, manifest_path);
  // The band is optional (a bake without `directional`, or of version 5): all three or none.
  const bool has_l1 = texels > 0 && files.value(kL1Keys[0], json()).is_string();
  for (size_t a = 0; a < 3; ++a)
    check_file_entry(files, kL1Keys[a], kL1Files[a], has_l1, manifest_path);
  // The soft map's band likewise (a bake without `directional`, or of version 5 or 6).
  const bool has_soft_l1 = texels > 0 && files.value(kSoftL1Keys[0], json()).is_string();
  for (size_t a = 0; a < 3; ++a)
    check_file_entry(files, kSoftL1Keys[a], kSoftL1Files[a], has_soft_l1, manifest_path);
  if (texels > 0) {
    maps.radiance = read_atlas_exr(directory, "illumination.exr", maps.width, maps.height,
                                   checksums, manifest_path);
    bake.soft_texels.radiance = read_atlas_exr(directory, "soft_light.exr", maps.width,
                                               maps.height, checksums, manifest_path);
  }
  if (has_l1) {
    for (size_t a = 0; a < 3; ++a)
      maps.l1[a] = read_atlas_exr(directory, kL1Files[a], maps.width, maps.height, checksums,
                                  manifest_path);
    maps.l1_share.assign(texels, 1.0f);  // caustic light: the cosine law (illumination.h)
  }
  if (has_soft_l1)
    for (size_t a = 0; a < 3; ++a)
      bake.soft_texels.l1[a] = read_atlas_exr(directory, kSoftL1Files[a], maps.width,
                                              maps.height, checksums, manifest_path);
  check_recorded_checksum(checksums, directory, "radiosity.bin",
                          decode_radiosity(join(directory, "radiosity.bin"), scene,
                                           bake.radiosity),
                          manifest_path);
  if (bake.radiosity.meshes.size() != scene.meshes.size())
    throw std::runtime_error(join(directory, "radiosity.bin") + ": " +
                             std::to_string(bake.radiosity.meshes.size()) +
                             " meshes, the scene has " + std::to_string(scene.meshes.size()));
  for (size_t g = 0; g < bake.light_groups.size(); ++g) {
    const std::string radiosity = group_file(g, "radiosity.bin");
    if (texels > 0) {
      maps.group_radiance.push_back(read_atlas_exr(directory,
                                                   group_file(g, "illumination.exr").c_str(),
                                                   maps.width, maps.height, checksums,
                                                   manifest_path));
      bake.soft_texels.group_radiance.push_back(
          read_atlas_exr(directory, group_file(g, "soft_light.exr").c_str(), maps.width,
                         maps.height, checksums, manifest_path));
    }
    bake.radiosity.group_vertex_radiance.emplace_back();
    check_recorded_checksum(
        checksums, directory, radiosity.c_str(),
        decode_group_radiosity(join(directory, radiosity.c_str()), bake.radiosity,
                               bake.radiosity.group_vertex_radiance.back()),
        manifest_path);
  }
  return bake;
}

// Every setting by its key in bake_settings.h (the scene file's and the option's name), so a
// bake directory says how to reproduce itself.
json bake_settings_json(const BakeParams& params) {
  json settings = {{"quality", to_string(params.quality)}};
  for (const BakeSetting& setting : bake_settings()) {
    const double value = setting.get(params);
    if (setting.is_boolean())
      settings[setting.key] = value != 0.0;
    else if (setting.is_integer())
      settings[setting.key] = uint64_t(value);
    else
      settings[setting.key] = value;
  }
  return settings;
}

BakeParams bake_settings_from_json(const nlohmann::json& settings, const std::string& where) {
  if (!settings.is_object() || !settings.contains("quality"))
    throw std::runtime_error(where + ": records no bake settings in this build's form; rebake it");
  // The same checks as the command line's: the level by parse_quality (an unknown name is an
  // error, not the first level), each key by its type and its range.
  BakeParams params;
  try {
    const json& quality = settings.at("quality");
    if (!quality.is_string())
      throw std::invalid_argument(std::string("quality: expected a string, got ") +
                                  quality.type_name());
    try {
      params.quality = parse_quality(quality.get<std::string>());
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("quality: ") + e.what());
    }
    for (const auto& [key, value] : settings.items()) {
      if (key == "quality") continue;
      if (const RetiredBakeSetting* retired = find_retired_bake_setting(key)) {
        const double given = value.is_boolean() ? double(value.get<bool>())
                             : value.is_number() ? value.get<double>()
                                                 : std::nan("");
        if (const std::string problem = retired->check(given); !problem.empty())
          throw std::invalid_argument(key + ": " + problem);
        continue;
      }
      const BakeSetting* setting = find_bake_setting(key);
      if (!setting) throw std::invalid_argument(key + ": unknown bake setting");
      if (setting->is_boolean() ? !value.is_boolean() : !value.is_number())
        throw std::invalid_argument(key + ": expected " +
                                    (setting->is_boolean() ? "true or false" : "a number") +
                                    ", got " + value.type_name());
      setting->set(params, value.is_boolean() ? double(value.get<bool>()) : value.get<double>());
    }
  } catch (const std::exception& e) {
    throw std::runtime_error(where + ": settings." + e.what());
  }
  return params;
}

BakeParams read_bake_settings(const std::string& directory) {
  const std::string path = join(directory, "manifest.json");
  const json manifest = read_manifest(path);
  const json settings = manifest.is_object() ? manifest.value("settings", json()) : json();
  BakeParams params = bake_settings_from_json(settings, path);
  // The bake's own seed is recorded twice; two that differ mean an edited manifest.
  if (manifest.contains("seed"))
    check_recorded_seed(manifest.at("seed"), settings.value("seed", json()), path);
  return params;
}

}  // namespace lb
