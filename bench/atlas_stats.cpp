// bench_atlas_stats SCENE [--padding N] [--texel-size M] [--max-size N]
// Builds the lightmap atlas (bake/illumination/atlas.h) with every diffuse, non-emitting mesh
// included and prints one JSON object on stdout: the atlas size, texel size, padding, chart
// count, the used texel area (the charts' UV triangle areas, in texels) and the packing
// efficiency (used / atlas area), plus each included mesh in world space (positions,
// triangles, its texel size), so bench/atlas_packing.py can give xatlas the same surfaces.
// Bench only (not ctest).

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bake/illumination/atlas.h"
#include "bake/io/scene_load.h"

namespace {

double uv_area_texels(const lb::Atlas& atlas, const std::vector<lb::vec2>& uvs,
                      const std::vector<lb::uvec3>& triangles) {
  double area = 0.0;
  for (const lb::uvec3& t : triangles) {
    const glm::dvec2 a(uvs[t.x]), b(uvs[t.y]), c(uvs[t.z]);
    const glm::dvec2 e1 = b - a, e2 = c - a;
    area += 0.5 * std::abs(e1.x * e2.y - e1.y * e2.x);
  }
  return area * double(atlas.width) * double(atlas.height);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: bench_atlas_stats SCENE [--padding N] [--texel-size M] [--max-size N]\n");
    return 2;
  }
  lb::AtlasParams params;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string arg = argv[i];
    if (arg == "--padding") {
      params.padding = std::atoi(argv[i + 1]);
    } else if (arg == "--texel-size") {
      params.texel_size = float(std::atof(argv[i + 1]));
    } else if (arg == "--max-size") {
      params.max_size = std::atoi(argv[i + 1]);
    } else {
      std::fprintf(stderr, "bench_atlas_stats: unknown argument '%s'\n", arg.c_str());
      return 2;
    }
  }
  try {
    const lb::Scene scene = lb::load_scene(argv[1]).scene;
    std::vector<bool> include(scene.meshes.size(), false);
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
      const lb::Material& material = scene.materials[size_t(scene.meshes[m].material)];
      include[m] = material.is_diffuse() && !material.is_emitter();
    }
    const lb::Atlas atlas = lb::build_atlas(scene, include, params);
    nlohmann::json out;
    out["scene"] = argv[1];
    out["width"] = atlas.width;
    out["height"] = atlas.height;
    out["texel_size_m"] = atlas.texel_size;
    out["padding"] = params.padding;
    out["charts"] = atlas.charts.size();
    double used = 0.0;
    nlohmann::json meshes = nlohmann::json::array();
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
      if (!atlas.has_map(m)) continue;
      used += uv_area_texels(atlas, atlas.lightmap_uvs[m], atlas.triangles_of(scene, m));
      const lb::Mesh& mesh = scene.meshes[m];
      float texel = atlas.texel_size;
      for (const lb::AtlasChart& chart : atlas.charts)
        if (chart.mesh == int(m)) texel = chart.texel_size;
      nlohmann::json positions = nlohmann::json::array(), triangles = nlohmann::json::array();
      for (const lb::vec3& p : mesh.positions) positions.insert(positions.end(), {p.x, p.y, p.z});
      for (const lb::uvec3& t : mesh.triangles) triangles.insert(triangles.end(), {t.x, t.y, t.z});
      meshes.push_back({{"name", mesh.name},
                        {"texel_size_m", texel},
                        {"positions", positions},
                        {"triangles", triangles}});
    }
    nlohmann::json rects = nlohmann::json::array();
    for (const lb::AtlasChart& chart : atlas.charts)
      rects.push_back({chart.offset.x, chart.offset.y, chart.size.x, chart.size.y});
    out["chart_rects"] = rects;  // x, y, width, height in texels
    out["used_texels"] = used;
    out["efficiency"] = atlas.width > 0 ? used / (double(atlas.width) * atlas.height) : 0.0;
    out["meshes"] = meshes;
    for (const std::string& warning : atlas.warnings)
      std::fprintf(stderr, "bench_atlas_stats: %s\n", warning.c_str());
    std::printf("%s\n", out.dump().c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_atlas_stats: %s\n", e.what());
    return 1;
  }
}
