// The lightmap atlas: charts that never share a texel node, every triangle covered, node
// areas that sum to the mesh area, and no seam where a chart border crosses a flat wall.
#include <gtest/gtest.h>

#include <span>

#include <cmath>
#include <numbers>

#include "bake/illumination/atlas.h"
#include "bake/illumination/given_uvs.h"
#include "bake/illumination/illumination.h"
#include "bake/sampling.h"
#include "test_helpers.h"

namespace lb {
namespace {

Scene room_scene() {
  Scene scene;
  const int white = test::add_material(scene, Material{});
  scene.meshes.push_back(test::make_box({-2, -2, 0}, {2, 2, 2.5f}, white, true, "room"));
  scene.meshes.push_back(
      test::make_box({-0.5f, -0.5f, 0}, {0.5f, 0.5f, 0.8f}, white, false, "table"));
  scene.meshes.push_back(test::make_sphere({1, 1, 1}, 0.3f, 12, 24, white, false, "ball"));
  return scene;
}

vec2 uv_at(const Atlas& atlas, const Mesh& mesh, size_t m, size_t t, vec2 b) {
  const uvec3 tri = mesh.triangles[t];
  const auto& uv = atlas.lightmap_uvs[m];
  return (1 - b.x - b.y) * uv[tri.x] + b.x * uv[tri.y] + b.y * uv[tri.z];
}

TEST(Atlas, ChartsNeverShareANodeAndAreaSumsToMeshArea) {
  const Scene scene = room_scene();
  const std::vector<bool> include = {true, true, false};
  const Atlas atlas = build_atlas(scene, include, AtlasParams{});
  ASSERT_GT(atlas.width, 0);
  EXPECT_LE(atlas.width, 2048);
  EXPECT_LE(atlas.height, 2048);
  // A 4 x 4 x 2.5 m room: the automatic rule gives 2-5 cm texels.
  EXPECT_GT(atlas.texel_size, 0.02f);
  EXPECT_LT(atlas.texel_size, 0.05f);
  EXPECT_TRUE(atlas.lightmap_uvs[2].empty());
  EXPECT_EQ(atlas.charts.size(), 12u);  // six faces each for the room and the table

  // The nodes a chart can touch are its rectangle grown by one node; they must be disjoint
  // between charts, and every chart UV must lie within half a texel of its rectangle: between
  // the centres of those outermost nodes, so its bilinear footprint is those nodes (atlas.h).
  std::vector<int> owner(size_t(atlas.width) * size_t(atlas.height), -1);
  for (size_t c = 0; c < atlas.charts.size(); ++c) {
    const AtlasChart& chart = atlas.charts[c];
    for (int j = chart.offset.y - 1; j <= chart.offset.y + chart.size.y; ++j)
      for (int i = chart.offset.x - 1; i <= chart.offset.x + chart.size.x; ++i) {
        ASSERT_TRUE(i >= 0 && j >= 0 && i < atlas.width && j < atlas.height);
        int& o = owner[atlas.node_index(i, j)];
        ASSERT_EQ(o, -1) << "charts " << o << " and " << c << " share node " << i << "," << j;
        o = int(c);
      }
    const Mesh& mesh = scene.meshes[size_t(chart.mesh)];
    for (uint32_t t : chart.triangles)
      for (int k = 0; k < 3; ++k) {
        const vec2 p = atlas.lightmap_uvs[size_t(chart.mesh)][mesh.triangles[t][k]] *
                       vec2(float(atlas.width), float(atlas.height));
        EXPECT_GE(p.x, float(chart.offset.x) - 0.5f);
        EXPECT_LE(p.x, float(chart.offset.x + chart.size.x) + 0.5f);
        EXPECT_GE(p.y, float(chart.offset.y) - 0.5f);
        EXPECT_LE(p.y, float(chart.offset.y + chart.size.y) + 0.5f);
      }
  }
  // Node areas (exact integrals of the bilinear weights) sum to the included meshes' area.
  double nodes = 0.0;
  for (float a : atlas.texel_area) nodes += a;
  const double meshes = mesh_area(scene.meshes[0]) + mesh_area(scene.meshes[1]);
  EXPECT_NEAR(nodes / meshes, 1.0, 1e-4);
}

TEST(Atlas, EveryTriangleIsCoveredByValidNodes) {
  const Scene scene = room_scene();
  const Atlas atlas = build_atlas(scene, {true, true, false}, AtlasParams{});
  Rng rng(7);
  for (size_t m = 0; m < 2; ++m) {
    const Mesh& mesh = scene.meshes[m];
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
      for (int s = 0; s < 64; ++s) {
        const vec2 b = square_to_triangle(rng.next_2d());
        NodeWeights nw;
        ASSERT_TRUE(node_weights(atlas, scene, uint32_t(m), uint32_t(t), b, nw));
        for (int k = 0; k < 4; ++k)
          if (nw.weight[k] > 1e-6f) {
            EXPECT_TRUE(atlas.valid[nw.index[k]]) << "mesh " << m << " triangle " << t;
            EXPECT_GT(atlas.texel_area[nw.index[k]], 0.0f);
          }
      }
    }
  }
}

// A flat wall made of two meshes (two glTF primitives, say): two charts whose border crosses
// the wall. Light deposited with a uniform density must read back uniform everywhere, across
// the border included.
TEST(Atlas, NoSeamWhereAChartBorderCrossesAFlatWall) {
  Scene scene;
  const int white = test::add_material(scene, Material{});
  const Mesh wall = test::make_quad({0, 0, 0}, {1.03f, 0, 0}, {0, 0, 1}, white, "wall");
  const Mesh right = test::make_quad({1.03f, 0, 0}, {0.97f, 0, 0}, {0, 0, 1}, white, "right");
  scene.meshes.push_back(wall);
  scene.meshes.push_back(right);
  AtlasParams params;
  params.texel_size = 0.05f;
  const Atlas atlas = build_atlas(scene, {true, true}, params);
  ASSERT_EQ(atlas.charts.size(), 2u);

  // Deposit density rho = 1 W/m^2 as a fine midpoint grid of little bundles per triangle.
  std::vector<glm::dvec3> power(atlas.texel_area.size(), glm::dvec3(0.0));
  const int grid = 400;
  for (uint32_t m = 0; m < 2; ++m) {
    const Mesh& mesh = scene.meshes[m];
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
      const double bundle = triangle_area(mesh, t) / double(grid * grid);
      for (int j = 0; j < grid; ++j)
        for (int i = 0; i < grid; ++i) {
          const vec2 b = square_to_triangle(stratified(i, j, grid, grid, vec2(0.5f)));
          NodeWeights nw;
          node_weights(atlas, scene, m, uint32_t(t), b, nw);
          for (int k = 0; k < 4; ++k) power[nw.index[k]] += glm::dvec3(bundle * nw.weight[k]);
        }
    }
  }
  std::vector<vec3> radiance = power_to_radiance(atlas, power);
  dilate(atlas, radiance, 3);
  const float expected = 1.0f / std::numbers::pi_v<float>;
  // Read the map along a line across the border, as the viewer would (bilinear lookup).
  float worst = 0.0f;
  for (int s = 0; s <= 200; ++s) {
    const float x = 0.83f + 0.4f * float(s) / 200.0f;  // crosses x = 1.03
    const vec3 p(x, 0.0f, 0.5f);
    const size_t m = x < 1.03f ? 0 : 1;
    const Mesh& mesh = scene.meshes[m];
    const uvec3 tri = mesh.triangles[0];
    const vec3 a = mesh.positions[tri.x], e1 = mesh.positions[tri.y] - a,
               e2 = mesh.positions[tri.z] - a, d = p - a;
    const float d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
    const float det = d11 * d22 - d12 * d12;
    const vec2 b((d22 * glm::dot(d, e1) - d12 * glm::dot(d, e2)) / det,
                 (d11 * glm::dot(d, e2) - d12 * glm::dot(d, e1)) / det);
    // The chart's projection is affine, so triangle 0's barycentrics serve for the whole
    // quad even where they leave [0,1].
    const vec3 value = sample_map(atlas, radiance, uv_at(atlas, mesh, m, 0, b));
    worst = std::max(worst, std::abs(value.x / expected - 1.0f));
  }
  EXPECT_LT(worst, 0.01f) << "largest relative deviation along the line across the border";

  // Dilation: every empty node next to a chart now holds the chart's value, so filtering (and
  // mipmapping) at the border never pulls in black.
  int filled = 0;
  for (int j = 1; j + 1 < atlas.height; ++j)
    for (int i = 1; i + 1 < atlas.width; ++i) {
      if (atlas.valid[atlas.node_index(i, j)]) continue;
      bool next_to_chart = false;
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di)
          next_to_chart = next_to_chart || atlas.valid[atlas.node_index(i + di, j + dj)];
      if (!next_to_chart) continue;
      EXPECT_NEAR(radiance[atlas.node_index(i, j)].x / expected, 1.0f, 0.05f) << i << "," << j;
      ++filled;
    }
  // At the default padding of 3 the two charts lie one empty node column apart and touch the
  // atlas border (atlas.h: no border nodes at padding 3), so the nodes checked are that column:
  // as tall as the charts (20 nodes, 1 m at 5 cm).
  EXPECT_GE(filled, 20);
}

// A flat-shaded export splits vertices everywhere; charts still grow across the splits.
TEST(Atlas, SplitVerticesAreWeldedForChartGrowth) {
  Scene scene;
  const int white = test::add_material(scene, Material{});
  Mesh tiles;
  tiles.name = "tiles";
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const Mesh q = test::make_quad({float(i), float(j), 0}, {1, 0, 0}, {0, 1, 0}, white);
      const uint32_t base = uint32_t(tiles.positions.size());
      tiles.positions.insert(tiles.positions.end(), q.positions.begin(), q.positions.end());
      for (uvec3 t : q.triangles) tiles.triangles.push_back(t + uvec3(base));
    }
  scene.meshes.push_back(tiles);
  const Atlas atlas = build_atlas(scene, {true}, AtlasParams{});
  ASSERT_EQ(atlas.charts.size(), 1u);
  double nodes = 0.0;
  for (float a : atlas.texel_area) nodes += a;
  EXPECT_NEAR(nodes / mesh_area(tiles), 1.0, 1e-4);
}

TEST(Atlas, GivenLightmapUvsAreKeptAndOverlapsReported) {
  Scene scene;
  const int white = test::add_material(scene, Material{});
  Mesh quad = test::make_quad({0, 0, 0}, {2, 0, 0}, {0, 1, 0}, white, "given");
  quad.lightmap_uvs = {{0.1f, 0.1f}, {0.9f, 0.1f}, {0.9f, 0.5f}, {0.1f, 0.5f}};
  scene.meshes.push_back(quad);
  Atlas atlas = build_atlas(scene, {true}, AtlasParams{});
  ASSERT_EQ(atlas.charts.size(), 1u);
  EXPECT_TRUE(atlas.charts[0].given_uvs);
  EXPECT_TRUE(atlas.warnings.empty());
  // Same layout up to a uniform scale and a shift: UV differences keep their ratios.
  const auto& uv = atlas.lightmap_uvs[0];
  const vec2 du = (uv[1] - uv[0]) * vec2(float(atlas.width), float(atlas.height));
  const vec2 dv = (uv[3] - uv[0]) * vec2(float(atlas.width), float(atlas.height));
  EXPECT_NEAR(du.x / dv.y, 2.0f, 1e-3f);
  EXPECT_NEAR(du.y, 0.0f, 1e-3f);

  // Fold the UVs so the two triangles overlap: one warning names the mesh, the problem and
  // what was done (new UVs, which neither fold nor overlap).
  scene.meshes[0].lightmap_uvs = {{0.1f, 0.1f}, {0.9f, 0.1f}, {0.9f, 0.5f}, {0.8f, 0.05f}};
  atlas = build_atlas(scene, {true}, AtlasParams{});
  ASSERT_EQ(atlas.warnings.size(), 1u);
  EXPECT_EQ(atlas.warnings[0],
            "mesh 'given': its lightmap UVs have 2 overlapping and 1 flipped of 2 triangles; "
            "generated new ones (two surfaces would share texels)");
  ASSERT_FALSE(atlas.charts.empty());
  for (const AtlasChart& chart : atlas.charts) EXPECT_FALSE(chart.given_uvs);
}

// A grid of n x n quads, UVs (x, y) / n: sound UVs in one island.
Mesh uv_grid(int n, int material) {
  Mesh mesh;
  mesh.name = "grid";
  mesh.material = material;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      mesh.positions.push_back(vec3(float(i), float(j), 0.0f));
      mesh.normals.push_back(vec3(0, 0, 1));
      mesh.lightmap_uvs.push_back(vec2(float(i), float(j)) / float(n));
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n) + 2,
                     d = a + uint32_t(n) + 1;
      mesh.triangles.push_back({a, b, c});
      mesh.triangles.push_back({a, c, d});
    }
  return mesh;
}

TEST(GivenUvs, CountsZeroAreaFlippedAndOverlappingTriangles) {
  Mesh mesh = uv_grid(4, 0);
  GivenUvCheck check = check_given_uvs(mesh);
  EXPECT_EQ(check.islands, 1);
  EXPECT_EQ(check.zero_area + check.flipped + check.overlapping, 0u);

  // One corner vertex pulled onto its neighbour: its lone triangle has no area.
  Mesh collapsed = mesh;
  collapsed.lightmap_uvs[0] = collapsed.lightmap_uvs[1];
  check = check_given_uvs(collapsed);
  EXPECT_EQ(check.zero_area, 1u);
  EXPECT_FALSE(check.folds());
  EXPECT_EQ(check.describe(), "1 zero-area of 32 triangles");

  // The same corner collapsed in space as well (a sliver, as the contact cuts make): no fault
  // of the UVs, not counted.
  Mesh sliver = collapsed;
  sliver.positions[0] = sliver.positions[1] + 1e-5f * (sliver.positions[0] - sliver.positions[1]);
  EXPECT_EQ(check_given_uvs(sliver).zero_area, 0u);

  // An inner vertex dragged across its neighbours: the island folds over itself.
  Mesh folded = mesh;
  folded.lightmap_uvs[6] = vec2(0.6f, 0.3f);  // vertex (1, 1) past (2, 1)
  check = check_given_uvs(folded);
  EXPECT_GT(check.flipped, 0u);
  EXPECT_GT(check.overlapping, 0u);

  // A second copy stacked on the first (the same UVs: an atlas of repeated parts): every
  // triangle shares its texels with its twin.
  Mesh stacked = mesh;
  const uint32_t offset = uint32_t(mesh.positions.size());
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    stacked.positions.push_back(mesh.positions[v] + vec3(0, 0, 1));
    stacked.normals.push_back(mesh.normals[v]);
    stacked.lightmap_uvs.push_back(mesh.lightmap_uvs[v]);
  }
  for (const uvec3& t : mesh.triangles) stacked.triangles.push_back(t + uvec3(offset));
  check = check_given_uvs(stacked);
  EXPECT_EQ(check.islands, 1);
  EXPECT_EQ(check.overlapping, 64u);
  EXPECT_EQ(check.flipped, 0u);
}

// Two islands laid out a hundredth of a UV unit apart (under a texel at the atlas's density):
// each becomes a chart of its own, packed with the padding, so no node holds both, and each
// keeps its layout.
TEST(GivenUvs, IslandsArePackedApartAtTheAtlasDensity) {
  Scene scene;
  const int white = test::add_material(scene, Material{});
  Mesh mesh = uv_grid(2, white);
  Mesh right = uv_grid(2, white);
  const uint32_t offset = uint32_t(mesh.positions.size());
  for (size_t v = 0; v < right.positions.size(); ++v) {
    mesh.positions.push_back(right.positions[v] + vec3(5, 0, 0));
    mesh.normals.push_back(right.normals[v]);
    mesh.lightmap_uvs.push_back(right.lightmap_uvs[v] * 0.49f + vec2(0.5f, 0.0f));
  }
  for (vec2& uv : std::span(mesh.lightmap_uvs).first(offset)) uv *= 0.49f;
  for (const uvec3& t : right.triangles) mesh.triangles.push_back(t + uvec3(offset));
  scene.meshes.push_back(mesh);
  AtlasParams params;
  params.texel_size = 0.1f;
  const Atlas atlas = build_atlas(scene, {true}, params);
  EXPECT_TRUE(atlas.warnings.empty()) << atlas.warnings.front();
  ASSERT_EQ(atlas.charts.size(), 2u);
  for (const AtlasChart& chart : atlas.charts) EXPECT_TRUE(chart.given_uvs);
  // No node lies in both charts' grown rectangles (atlas.h: a chart's nodes are its rectangle
  // grown by one node each side).
  const AtlasChart &a = atlas.charts[0], &b = atlas.charts[1];
  const bool apart_x = a.offset.x + a.size.x + 1 < b.offset.x - 1 ||
                       b.offset.x + b.size.x + 1 < a.offset.x - 1;
  const bool apart_y = a.offset.y + a.size.y + 1 < b.offset.y - 1 ||
                       b.offset.y + b.size.y + 1 < a.offset.y - 1;
  EXPECT_TRUE(apart_x || apart_y);
  // Texel areas still sum to the mesh's area: nothing shared, nothing lost.
  double nodes = 0.0;
  for (float area : atlas.texel_area) nodes += area;
  EXPECT_NEAR(nodes / mesh_area(scene.meshes[0]), 1.0, 1e-4);
  // With generate_lightmap_uvs the given UVs are not used at all.
  params.generate_lightmap_uvs = true;
  for (const AtlasChart& chart : build_atlas(scene, {true}, params).charts)
    EXPECT_FALSE(chart.given_uvs);
}

// A smooth closed sphere shares its vertices everywhere. The atlas cuts it into charts by
// splitting the vertices charts share; no triangle moves, and the map covers it all.
TEST(Atlas, SmoothSphereIsCutIntoChartsBySplittingSharedVertices) {
  Scene scene;
  const int white = test::add_material(scene, Material{});
  scene.meshes.push_back(test::make_sphere({0, 0, 0}, 1.0f, 8, 16, white, false, "ball"));
  const Mesh& ball = scene.meshes[0];
  const Atlas atlas = build_atlas(scene, {true}, AtlasParams{});
  ASSERT_TRUE(atlas.has_map(0));
  EXPECT_EQ(atlas.warnings.size(), 0u);  // no folded chart either
  EXPECT_GT(atlas.charts.size(), 4u);
  const VertexSplit& split = atlas.vertex_splits[0];
  ASSERT_FALSE(split.empty());
  const Mesh cut = split_vertices(ball, split);
  ASSERT_EQ(cut.triangles.size(), ball.triangles.size());
  ASSERT_EQ(atlas.lightmap_uvs[0].size(), cut.positions.size());
  EXPECT_EQ(&atlas.triangles_of(scene, 0), &split.triangles);
  // Corner for corner the same triangles, with their normals and texture UVs.
  for (size_t t = 0; t < ball.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = ball.triangles[t][k], b = cut.triangles[t][k];
      ASSERT_EQ(cut.positions[b], ball.positions[a]) << t;
      ASSERT_EQ(cut.normals[b], ball.normals[a]) << t;
      ASSERT_EQ(cut.uvs[b], ball.uvs[a]) << t;
    }
  // No vertex of the cut mesh belongs to two charts.
  std::vector<int> chart_of_vertex(cut.positions.size(), -1);
  for (size_t c = 0; c < atlas.charts.size(); ++c)
    for (uint32_t t : atlas.charts[c].triangles)
      for (int k = 0; k < 3; ++k) {
        int& owner = chart_of_vertex[cut.triangles[t][k]];
        if (owner < 0) owner = int(c);
        ASSERT_EQ(owner, int(c)) << "vertex " << cut.triangles[t][k];
      }
  // Node areas sum to the sphere's area and every triangle lands on valid nodes.
  double nodes = 0.0;
  for (float a : atlas.texel_area) nodes += a;
  EXPECT_NEAR(nodes / mesh_area(ball), 1.0, 1e-4);
  Rng rng(11);
  for (size_t t = 0; t < ball.triangles.size(); ++t)
    for (int s = 0; s < 16; ++s) {
      NodeWeights nw;
      ASSERT_TRUE(
          node_weights(atlas, scene, 0, uint32_t(t), square_to_triangle(rng.next_2d()), nw));
      for (int k = 0; k < 4; ++k)
        EXPECT_TRUE(nw.weight[k] <= 1e-6f || atlas.valid[nw.index[k]]) << "triangle " << t;
    }
}

// Meshes whose vertices are already apart where charts meet (boxes, flat-shaded exports)
// need no split.
TEST(Atlas, MeshesSplitAtTheirCreasesAreNotSplitAgain) {
  const Scene scene = room_scene();
  const Atlas atlas = build_atlas(scene, {true, true, false}, AtlasParams{});
  EXPECT_TRUE(atlas.vertex_splits[0].empty());
  EXPECT_TRUE(atlas.vertex_splits[1].empty());
  EXPECT_EQ(atlas.lightmap_uvs[0].size(), scene.meshes[0].positions.size());
}

TEST(Atlas, DiskToSquareInvertsTheConcentricMap) {
  Rng rng(3);
  for (int k = 0; k < 1000; ++k) {
    const vec2 u = rng.next_2d();
    const vec2 back = disk_to_square(square_to_disk(u));
    EXPECT_NEAR(back.x, u.x, 1e-4f);
    EXPECT_NEAR(back.y, u.y, 1e-4f);
  }
}

}  // namespace
}  // namespace lb
