// Thin charts unfolded into strips (bake/illumination/atlas_unfold.h): the four sides of a thin
// table leg become one chart, laid out isometrically (every UV edge as long as its world edge
// at the chart's texel size, stretch 1), with the atlas invariants kept.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "bake/illumination/atlas.h"
#include "bake/io/shapes.h"
#include "test_helpers.h"

namespace lb {
namespace {

struct StripStats {
  double stretch = 0.0;     // largest |UV edge length * texel / world edge length - 1|
  double edge_error = 0.0;  // largest |UV edge length - world edge length / texel|, texels
  double area_ratio = 0.0;  // sum of node areas / mesh area
  int shared_nodes = 0;     // nodes inside two charts' rectangles grown by one
};

StripStats measure(const Scene& scene, const Atlas& atlas) {
  StripStats stats;
  const Mesh& original = scene.meshes[0];
  const Mesh mesh = split_vertices(original, atlas.vertex_splits[0]);
  const auto& uvs = atlas.lightmap_uvs[0];
  const vec2 scale(float(atlas.width), float(atlas.height));
  for (const AtlasChart& chart : atlas.charts)
    for (uint32_t t : chart.triangles)
      for (int k = 0; k < 3; ++k) {
        const uint32_t a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
        const double world = glm::length(glm::dvec3(mesh.positions[b] - mesh.positions[a]));
        const double flat = glm::length(glm::dvec2((uvs[b] - uvs[a]) * scale)) * chart.texel_size;
        stats.stretch = std::max(stats.stretch, std::abs(flat / world - 1.0));
        stats.edge_error =
            std::max(stats.edge_error, std::abs(flat - world) / double(chart.texel_size));
      }
  double nodes = 0.0;
  for (float a : atlas.texel_area) nodes += a;
  stats.area_ratio = nodes / mesh_area(original);
  std::vector<int> owner(atlas.texel_area.size(), -1);
  for (size_t c = 0; c < atlas.charts.size(); ++c) {
    const AtlasChart& chart = atlas.charts[c];
    for (int j = chart.offset.y - 1; j <= chart.offset.y + chart.size.y; ++j)
      for (int i = chart.offset.x - 1; i <= chart.offset.x + chart.size.x; ++i) {
        int& o = owner[atlas.node_index(i, j)];
        if (o >= 0) ++stats.shared_nodes;
        o = int(c);
      }
  }
  return stats;
}

Scene box_scene(vec3 hi, const char* name) {
  Scene scene;
  const int white = test::add_material(scene, Material{});
  scene.meshes.push_back(test::make_box({0, 0, 0}, hi, white, false, name));
  return scene;
}

Atlas atlas_at(const Scene& scene, float texel) {
  AtlasParams params;
  params.texel_size = texel;
  return build_atlas(scene, {true}, params);
}

// A 5 x 5 cm leg 80 cm long at 2.5 cm texels: four sides two texels wide and two end caps.
// Without unfolding that is six charts, each paying its padding on a two-texel rectangle.
TEST(AtlasUnfold, ThinBoxLegBecomesOneIsometricStrip) {
  const Scene scene = box_scene({0.05f, 0.8f, 0.05f}, "leg");
  const Atlas atlas = atlas_at(scene, 0.025f);
  EXPECT_TRUE(atlas.warnings.empty());  // no folded (overlapping) chart either
  EXPECT_LE(atlas.charts.size(), 2u);   // measured: 1 (the sides and both caps)
  const StripStats stats = measure(scene, atlas);
  EXPECT_LT(stats.stretch, 1e-5) << "measured " << stats.stretch;        // 2.2e-6
  EXPECT_LT(stats.edge_error, 1e-5) << "measured " << stats.edge_error;  // 4.3e-6 texels
  EXPECT_NEAR(stats.area_ratio, 1.0, 1e-4);                              // 1 + 2e-8
  EXPECT_EQ(stats.shared_nodes, 0);
  // Isometric: the chart's UV area in texels is the mesh area over the texel area.
  const vec2 scale(float(atlas.width), float(atlas.height));
  double uv_area = 0.0;
  const auto& uvs = atlas.lightmap_uvs[0];
  for (const uvec3& t : atlas.triangles_of(scene, 0)) {
    const vec2 e1 = (uvs[t.y] - uvs[t.x]) * scale, e2 = (uvs[t.z] - uvs[t.x]) * scale;
    uv_area += 0.5 * std::abs(double(e1.x) * e2.y - double(e1.y) * e2.x);
  }
  EXPECT_NEAR(uv_area * 0.025 * 0.025 / mesh_area(scene.meshes[0]), 1.0, 1e-5);
}

// Figure 5's table leg: a 16-sided cylinder 4 cm across at its 45.7 mm texels. The side is cut
// once where the strip closes (its seam vertices split), not into the four 40-degree charts the
// normal cone alone makes.
TEST(AtlasUnfold, ThinCylinderUnrollsIntoOneChart) {
  Scene scene;
  test::add_material(scene, Material{});
  Mesh leg = make_cylinder(0.02f, 0.0f, 0.71f, 16, true);
  leg.name = "leg";
  scene.meshes.push_back(leg);
  const Atlas atlas = atlas_at(scene, 0.0457f);
  EXPECT_TRUE(atlas.warnings.empty());
  EXPECT_EQ(atlas.charts.size(), 1u);
  const StripStats stats = measure(scene, atlas);
  // Its edges are 0.17 texels wide, so float UVs (2e-6 texels of error) limit the relative
  // stretch: measured 1.3e-5, against 8 % for the outer faces of a projected 40-degree chart.
  EXPECT_LT(stats.stretch, 3e-5) << "measured " << stats.stretch;
  EXPECT_LT(stats.edge_error, 1e-5) << "measured " << stats.edge_error;  // 2.2e-6 texels
  EXPECT_NEAR(stats.area_ratio, 1.0, 1e-4);                              // 1 - 1e-9
  EXPECT_EQ(stats.shared_nodes, 0);
}

// A box whose faces are many texels across is not thin: its six faces stay six charts.
TEST(AtlasUnfold, WideBoxKeepsItsFaces) {
  EXPECT_EQ(atlas_at(box_scene({1.0f, 0.8f, 1.0f}, "table"), 0.025f).charts.size(), 6u);
}

// Flat faces three texels across (the Cornell box's blocks at 5 texels/m) are not unfolded
// either: in a strip a third of a face's texels would straddle its 90-degree edges and mix the
// light of both faces. Curved charts that narrow still are (ThinCylinderUnrollsIntoOneChart).
TEST(AtlasUnfold, BoxOfThreeTexelFacesKeepsItsFaces) {
  EXPECT_EQ(atlas_at(box_scene({0.075f, 0.075f, 0.075f}, "block"), 0.025f).charts.size(), 6u);
}

}  // namespace
}  // namespace lb
