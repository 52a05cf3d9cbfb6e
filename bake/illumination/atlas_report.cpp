#include "bake/illumination/atlas_report.h"

#include <algorithm>

#include "bake/bake_result.h"
#include "bake/illumination/given_uvs.h"

namespace lb {

LightmapReport lightmap_report(const Scene& scene, float texel_size, int padding) {
  std::vector<bool> include(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    include[m] = scene.materials[size_t(scene.meshes[m].material)].is_diffuse();
  AtlasParams params;
  params.texel_size = texel_size;
  params.padding = padding;
  const Atlas atlas = build_atlas(scene, include, params);
  LightmapReport report;
  report.width = atlas.width;
  report.height = atlas.height;
  report.texels_per_m = texel_density(atlas.texel_size);
  report.warnings = atlas.warnings;
  for (uint8_t v : atlas.valid) report.valid_texels += v;
  // Charts never share a node: a chart's nodes are its rectangle grown by one (atlas.h).
  std::vector<size_t> texels(scene.meshes.size(), 0), charts(scene.meshes.size(), 0);
  std::vector<uint8_t> any_given(scene.meshes.size(), 0);
  for (const AtlasChart& chart : atlas.charts) {
    ++charts[size_t(chart.mesh)];
    any_given[size_t(chart.mesh)] |= chart.given_uvs;
    for (int j = std::max(0, chart.offset.y - 1);
         j <= std::min(atlas.height - 1, chart.offset.y + chart.size.y + 1); ++j)
      for (int i = std::max(0, chart.offset.x - 1);
           i <= std::min(atlas.width - 1, chart.offset.x + chart.size.x + 1); ++i)
        texels[size_t(chart.mesh)] += atlas.valid[atlas.node_index(i, j)];
  }
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    if (!atlas.has_map(m)) continue;
    MeshLightmapRow row;
    row.mesh = m;
    row.texels_per_m = texel_density(atlas.mesh_texel_size[m]);
    row.charts = charts[m];
    row.texels = texels[m];
    const Mesh& mesh = scene.meshes[m];
    if (mesh.lightmap_uvs.size() != mesh.positions.size()) {
      row.uvs = "generated";
    } else {
      const GivenUvCheck check = check_given_uvs(mesh);
      const bool problems = check.folds() || check.zero_area > 0;
      row.uvs = any_given[m] ? "own, " + std::to_string(check.islands) + " islands" : "generated";
      if (problems) row.uvs += " (own UVs: " + check.describe() + ")";
    }
    report.meshes.push_back(row);
  }
  return report;
}

}  // namespace lb
