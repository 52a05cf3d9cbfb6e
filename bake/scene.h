#pragma once
// The scene as plain data: world-space triangle meshes, materials, textures, cameras.
// Loaders fill it, the bake passes read it (`const Scene&`), nothing in here knows about
// Embree or OpenGL. Units: metres for positions, W/(sr m^2) per RGB channel for radiance.

#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bake/probe_grid_data.h"
#include "bake/quality.h"

namespace lb {

using glm::uvec3;
using glm::vec2;
using glm::vec3;
using glm::vec4;

// Rec. 709 luminance of a linear RGB colour: the weight lights and sky texels are chosen by.
inline float luminance(vec3 rgb) {
  return 0.2126f * rgb.r + 0.7152f * rgb.g + 0.0722f * rgb.b;
}

// A decoded texture. Colour textures are stored linear (sRGB decoded at load time);
// data textures (height and normal maps) are stored as they were in the file.
// How a texture is read between and beyond its texels: glTF's sampler (Blender's Image Texture
// interpolation Closest / Linear and extension Repeat / Extend / Mirror).
enum class TextureFilter : uint8_t { linear, nearest };
enum class TextureWrap : uint8_t { repeat, clamp, mirror };

struct Texture {
  std::string path;  // where it came from, for messages
  int width = 0;
  int height = 0;
  int channels = 0;           // 1..4
  std::vector<float> texels;  // row-major, top row first, `channels` floats per texel
  bool srgb_decoded = false;
  TextureFilter filter = TextureFilter::linear;
  TextureWrap wrap_u = TextureWrap::repeat, wrap_v = TextureWrap::repeat;
};

enum class MaterialKind {
  diffuse,  // Lambertian, reflectance = albedo
  mirror,   // perfect specular reflection, reflectance = specular colour
  glass,    // dielectric, Fresnel reflect/refract, reflectance = transmittance colour
  glossy,   // rough metal ("brushed plates"), reflectance = specular colour, roughness > 0
};

const char* to_string(MaterialKind kind);

enum class BumpKind {
  none,
  height,      // Blinn bump: a height map, `bump_scale` metres per unit of texture value
  normal_map,  // tangent-space normal map (glTF convention), `bump_scale` scales x and y
};

struct Material {
  std::string name;
  MaterialKind kind = MaterialKind::diffuse;
  vec3 reflectance{0.8f};        // in [0,1]: albedo, specular colour or transmittance
  int reflectance_texture = -1;  // index into Scene::textures, multiplies `reflectance`
  float ior = 1.5f;              // glass only, >= 1
  float roughness = 0.0f;        // glossy only, in (0,1]: GGX alpha = roughness^2
  vec3 emission{0.0f};           // emitted radiance, W/(sr m^2), on the front side
  // The back emits `emission` too (glTF `doubleSided`, TOML `double_sided`): glTF shades a
  // double-sided material's back with the normal reversed, and Cycles and three.js light both.
  bool two_sided_emission = false;
  // The back reflects as the front does, with the normal reversed (glTF `doubleSided` on a
  // diffuse material, TOML `double_sided`): light reaching the back of a thin surface (a
  // panel, a leaf, a sheet) is reflected there rather than absorbed. Only the radiosity pass
  // transports it (it shoots the back's reflected power from the back); the stored light is
  // still the front's, so the back of a thin surface shows its front's baked light.
  bool two_sided_reflection = false;
  // glTF alphaMode MASK: the surface is absent where alpha = alpha_factor x alpha_texture (at
  // the hit's `uvs`, 1 without a texture) is below alpha_cutoff. Every ray-traced pass sees the
  // cut-outs (an Embree filter in accel.cpp); off unless alpha_mask.
  bool alpha_mask = false;
  // glTF alphaMode BLEND, approximated by stochastic transparency: every ray-traced pass counts
  // a hit with probability alpha (a hash of the ray and the hit, accel.cpp), so 1 - alpha of
  // the light passes on average, uncoloured. Off unless alpha_blend; alpha_cutoff unused.
  bool alpha_blend = false;
  float alpha_cutoff = 0.5f;
  float alpha_factor = 1.0f;
  int alpha_texture = -1;  // index into Scene::textures, one channel (alpha, linear); -1: none
  BumpKind bump = BumpKind::none;
  int bump_texture = -1;
  float bump_scale = 1.0f;
  // The light group an emitting material's light belongs to (bake/light_groups.h); empty:
  // the group `default`.
  std::string light_group;

  bool is_emitter() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }
  // Diffuse surfaces receive baked light; the rest only redirect it.
  bool is_diffuse() const { return kind == MaterialKind::diffuse; }
};

// Where an emitting mesh's illumination rays (pass 1) start: its centre gives sharp caustics
// and less noise, points over the whole light soft caustics; `automatic` decides by the
// light's angle seen from the nearest specular object (bake/illumination/light_rays.h,
// kCentreOriginMaxAngle). The one way to choose them.
enum class CausticOrigins : uint8_t { automatic, centre, over_light };

// Per-mesh bake settings; 0 sizes mean "choose from the scene's scale".
struct MeshBakeSettings {
  float texel_size = 0.0f;  // illumination map texel edge, metres
  float patch_size = 0.0f;  // radiosity patch edge, metres
  CausticOrigins caustic_origins = CausticOrigins::automatic;  // lights only
};

// A triangle mesh in world space (transforms and instances are applied by the loaders).
// Optional attribute arrays are either empty or as long as `positions`.
struct Mesh {
  std::string name;
  std::vector<vec3> positions;
  std::vector<vec3> normals;       // shading normals, unit length
  std::vector<vec2> uvs;           // texture coordinates
  std::vector<vec2> lightmap_uvs;  // illumination map coordinates (glTF TEXCOORD_1, or the atlas)
  std::vector<vec4> tangents;      // xyz tangent, w handedness (for normal maps)
  std::vector<uvec3> triangles;    // counter-clockwise seen from the front
  // Per triangle, 1 where it lies inside other geometry (under a block, in a wall's footprint),
  // set by conform_to_contacts (contact_conform.h) on meshes it cut; empty = not known. Only
  // read when as long as `triangles`: code that remakes the triangles clears it.
  std::vector<uint8_t> hidden;
  int material = 0;
  MeshBakeSettings bake;
  // A moving object (TOML `dynamic = true`, glTF node `extras.dynamic`): set by the loaders,
  // then load_scene moves the mesh to Scene::dynamic_meshes, out of the bake.
  bool dynamic = false;
  // A moving object's probe light as a lightbake export wrote it (`extras.lightbake_probe_sh`:
  // L2 radiance SH, bake/probe_grid.h's convention, 9 RGB coefficients); empty otherwise.
  std::vector<vec3> probe_sh;
};

struct Camera {
  std::string name;
  vec3 position{0.0f, 0.0f, 5.0f};
  vec3 target{0.0f};
  vec3 up{0.0f, 1.0f, 0.0f};
  float vertical_fov_deg = 50.0f;
  float aperture_radius = 0.0f;  // metres; 0 is a pinhole
  float focus_distance = 0.0f;   // metres; 0 focuses on `target`
  float exposure = 0.0f;         // stops: the default exposure of renders from this view
};

// A lamp: light from one point (point, spot) or from one direction (directional, the sun).
// Radiometric, as everything in the scene: the loaders convert glTF's photometric units at
// 683 lm/W (candela -> W/sr, lux -> W/m^2), see docs/gltf.md.
enum class LampKind : uint8_t { point, spot, directional };

// Luminous efficacy glTF's photometric light units are converted at (KHR_lights_punctual).
inline constexpr double kLumensPerWatt = 683.0;

const char* to_string(LampKind kind);

struct Lamp {
  std::string name;
  LampKind kind = LampKind::point;
  vec3 position{0.0f};                // point, spot: metres
  vec3 direction{0.0f, -1.0f, 0.0f};  // spot, directional: the way the light travels, unit
  // Point, spot: radiant intensity on the axis, W/sr per channel. Directional: irradiance on
  // a surface facing the light, W/m^2 per channel.
  vec3 intensity{0.0f};
  float range = 0.0f;             // point, spot: metres; 0 is unlimited (glTF `range`)
  float inner_cone = 0.0f;        // spot: radians from the axis where the falloff starts
  float outer_cone = 0.7853982f;  // spot: radians from the axis where the light ends (<= pi/2)
  std::string light_group;        // bake/light_groups.h; empty: the group `default`
};

// Light from every direction at infinity (outdoor scenes). Radiance towards direction d (from
// the scene to the sky) is `radiance` times the equirect image at d when there is one.
// Equirect convention: +Y up; image column u = 0.5 + atan2(d.x, -d.z) / (2 pi) (so -Z is the
// image's centre), row v = acos(d.y) / pi (top row looks straight up).
struct Sky {
  Sky(vec3 radiance_in = vec3(0.0f), int texture_in = -1)
      : radiance(radiance_in), texture(texture_in) {}
  vec3 radiance{0.0f};  // W/(sr m^2) per channel, multiplies the image
  int texture = -1;     // index into Scene::textures, a linear (HDR) equirect image; -1: none
  std::string light_group;  // bake/light_groups.h; empty: the group `default`
};

struct Scene {
  std::string source_path;  // file it was loaded from, for messages and manifests
  // Where this scene's origin lies in the file's coordinates, metres: (0,0,0) unless the scene
  // was far from its file's origin and recentre_far_scene moved it (see there).
  glm::dvec3 world_origin{0.0};
  std::vector<Mesh> meshes;
  // Moving objects: no pass, accelerator or renderer of baked light sees them (they neither
  // receive baked light nor cast into it); viewers draw them lit by the light probes
  // (bake/probe_grid.h). Same materials as `meshes`.
  std::vector<Mesh> dynamic_meshes;
  // The light-probe grid a lightbake export wrote (scene.extensions.LIGHTBAKE_light_probes,
  // docs/light-probes.md), in this scene's coordinates: the viewer blends it at each vertex of
  // a moving object. Empty otherwise (a bake's moving objects take probes baked anew).
  ProbeGrid probe_grid;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<Camera> cameras;
  // Lamps. Emissive meshes are lights as well (bake/lights.h collects them); a sky is the
  // light from infinity.
  std::vector<Lamp> lights;
  std::optional<Sky> sky;
  std::optional<Quality> quality;  // the file's own bake quality (TOML `[bake] quality`), if any
  // The file's other `[bake]` keys, as given: checked against the table of bake settings
  // (bake/pipeline/bake_settings.h) when a bake resolves its settings.
  struct BakeSettingValue {
    std::string key;
    double value = 0.0;  // booleans as 0 or 1
    std::string where;   // "file:line:col: bake.key", for errors
  };
  std::vector<BakeSettingValue> bake_settings;
};

struct Bounds {
  vec3 min{1e30f};
  vec3 max{-1e30f};
  void extend(vec3 p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  bool empty() const { return min.x > max.x; }
  vec3 extent() const { return empty() ? vec3(0.0f) : max - min; }
  float diagonal() const { return glm::length(extent()); }
};

Bounds scene_bounds(const Scene& scene);
size_t triangle_count(const Scene& scene);
float triangle_area(const Mesh& mesh, size_t triangle);
vec3 triangle_normal(const Mesh& mesh, size_t triangle);  // geometric, unit (zero if degenerate)

// Derivatives of position with respect to the texture coordinates over one triangle (bump
// mapping, tangents); nullopt if the mesh has no UVs or the triangle's UVs are degenerate.
struct UvDerivatives {
  vec3 dp_du{0.0f};
  vec3 dp_dv{0.0f};
};
std::optional<UvDerivatives> uv_derivatives(const Mesh& mesh, size_t triangle);
float mesh_area(const Mesh& mesh);

// Moves a scene that lies far from its origin (further than 64 m and twice its own size) so its
// bounding box is centred on (0,0,0), in whole metres, cameras included, and adds the move to
// `world_origin`; returns whether it moved. Why: ray offsets and intersections are relative
// to the coordinates' magnitude (a float's step at 1e4 m is 1 mm, at 1e5 m 8 mm), so a level
// 10 km out would leak light and show acne; centred, it renders as it would at the origin.
// The loaders call it; everything after them works in the centred frame.
bool recentre_far_scene(Scene& scene);

// Moves the meshes marked `dynamic` from `meshes` to `dynamic_meshes`, keeping their order.
void separate_dynamic_meshes(Scene& scene);

// Appends a copy of vertex `from` (every attribute) and returns its index.
uint32_t append_vertex_copy(Mesh& mesh, uint32_t from);

// Vertices split so that parts of a mesh can carry different per-vertex attributes (the
// lightmap atlas cuts a smooth mesh into charts this way). Triangles keep their order and
// their corner order, so a (triangle, barycentric) pair names the same point before and after.
struct VertexSplit {
  std::vector<uint32_t> copied_from;  // per appended vertex, the original vertex it copies
  std::vector<uvec3> triangles;       // every triangle, over the original + appended vertices
  bool empty() const { return triangles.empty(); }
};

// Whether a triangle has no area to speak of: twice its area at or below 1e-7 of its longest
// edge squared (the loaders drop such triangles; so do the contact cuts).
bool zero_area_triangle(vec3 a, vec3 b, vec3 c);

// The mesh with `split` applied (the mesh itself when the split is empty).
Mesh split_vertices(const Mesh& mesh, const VertexSplit& split);

}  // namespace lb
