// Gutters and mip levels (docs/export.md, "Gutters and mips"): how many levels of the map's mip
// chain keep every chart free of its neighbours' light, per `atlas_padding`. Each chart's light
// alone (1 on its nodes, 0 on every other chart's), the gutters filled as the export fills them
// (dilate_texels), then the box mip chain an engine builds (each level texel the mean of the
// 2 x 2 above it; basisu -mip_filter box for the KTX2) read bilinearly at level k at points all
// over the chart: it reads 1 where no other chart's light reaches it.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bake/illumination/atlas.h"
#include "bake/lightmap/texel_footprint.h"
#include "test_helpers.h"

namespace lb {
namespace {

// A box mip level from the one above: level k texel (i, j) is the mean of the level k - 1 texels
// (2i .. 2i + 1, 2j .. 2j + 1) inside it (the model is exact for sides divisible by 2^k).
struct Level {
  int width = 0, height = 0;
  std::vector<float> texels;
  float at(int i, int j) const {
    return texels[size_t(std::clamp(j, 0, height - 1)) * size_t(width) +
                  size_t(std::clamp(i, 0, width - 1))];
  }
};

Level half(const Level& above) {
  Level level{(above.width + 1) / 2, (above.height + 1) / 2, {}};
  level.texels.resize(size_t(level.width) * size_t(level.height));
  for (int j = 0; j < level.height; ++j)
    for (int i = 0; i < level.width; ++i) {
      float sum = 0.0f;
      int count = 0;
      for (int dj = 0; dj < 2; ++dj)
        for (int di = 0; di < 2; ++di)
          if (2 * i + di < above.width && 2 * j + dj < above.height)
            sum += above.at(2 * i + di, 2 * j + dj), ++count;
      level.texels[size_t(j) * size_t(level.width) + size_t(i)] = sum / float(count);
    }
  return level;
}

// Bilinear at level k (k = 0 the map), clamped to the edge, `uv` in the map's [0, 1]^2.
float read(const Level& level, int k, int width, int height, vec2 uv) {
  const float scale = 1.0f / float(1 << k);
  const float s = uv.x * float(width) * scale - 0.5f, t = uv.y * float(height) * scale - 0.5f;
  const int i = int(std::floor(s)), j = int(std::floor(t));
  const float fx = s - float(i), fy = t - float(j);
  return (1 - fx) * (1 - fy) * level.at(i, j) + fx * (1 - fy) * level.at(i + 1, j) +
         (1 - fx) * fy * level.at(i, j + 1) + fx * fy * level.at(i + 1, j + 1);
}

// Charts of many sizes: boxes from 0.25 to 1.3 m across and a sphere's curved charts.
Scene charts_scene() {
  Scene scene;
  const int white = test::add_material(scene, Material{});
  for (int k = 0; k < 5; ++k) {
    const float side = 0.25f + 0.27f * float(k), x = 1.5f * float(k);
    scene.meshes.push_back(test::make_box({x, 0, 0}, {x + side, 0.6f * side + 0.1f, side}, white,
                                          false, "box" + std::to_string(k)));
  }
  scene.meshes.push_back(test::make_sphere({0, 2, 0}, 0.45f, 16, 32, white, false, "ball"));
  return scene;
}

// The deepest mip level (at most kMaxLevel) down to which every chart reads only its own light,
// at 10 texels/m, whatever the charts' place against the mip levels' 2^k-node blocks: the map is
// shifted by 0 .. 2^kMaxLevel - 1 empty nodes along x, then along y.
constexpr int kMaxLevel = 4;

int clean_levels(const Scene& scene, int padding, size_t& charts) {
  AtlasParams params;
  params.texel_size = 0.1f;
  params.padding = padding;
  const Atlas atlas = build_atlas(scene, std::vector<bool>(scene.meshes.size(), true), params);
  charts = atlas.charts.size();
  int clean = kMaxLevel;
  for (int shift = 0; shift < 2 * (1 << kMaxLevel); ++shift) {
    const int sx = shift % (1 << kMaxLevel) * (shift < (1 << kMaxLevel) ? 1 : 0);
    const int sy = shift < (1 << kMaxLevel) ? 0 : shift - (1 << kMaxLevel);
    const int width = atlas.width + sx, height = atlas.height + sy;
    auto node = [&](int i, int j) { return size_t(j + sy) * size_t(width) + size_t(i + sx); };
    std::vector<uint8_t> valid(size_t(width) * size_t(height), 0);
    for (int j = 0; j < atlas.height; ++j)
      for (int i = 0; i < atlas.width; ++i) valid[node(i, j)] = atlas.valid[atlas.node_index(i, j)];
    for (size_t c = 0; c < atlas.charts.size() && clean > 0; ++c) {
      const AtlasChart& chart = atlas.charts[c];
      std::vector<vec3> light(valid.size(), vec3(0.0f));
      for (int j = chart.offset.y - 1; j <= chart.offset.y + chart.size.y; ++j)
        for (int i = chart.offset.x - 1; i <= chart.offset.x + chart.size.x; ++i)
          if (atlas.valid[atlas.node_index(i, j)]) light[node(i, j)] = vec3(1.0f);
      // Rings beyond 2^(kMaxLevel + 1) are never read by these levels: they need not be filled.
      dilate_texels(width, height, valid, light, 2 << kMaxLevel);
      std::vector<Level> chain(1, Level{width, height, {}});
      for (const vec3& v : light) chain[0].texels.push_back(v.x);
      while (int(chain.size()) <= clean) chain.push_back(half(chain.back()));
      // Points all over the chart's triangles, corners and edges included.
      const std::vector<uvec3>& triangles = atlas.triangles_of(scene, size_t(chart.mesh));
      const std::vector<vec2>& uvs = atlas.lightmap_uvs[size_t(chart.mesh)];
      for (int k = 1; k <= clean; ++k)
        for (uint32_t t : chart.triangles) {
          bool own = true;
          constexpr int kSteps = 8;
          for (int a = 0; a <= kSteps && own; ++a)
            for (int b = 0; a + b <= kSteps && own; ++b) {
              const float wa = float(a) / kSteps, wb = float(b) / kSteps;
              const uvec3 tri = triangles[t];
              const vec2 uv = (1 - wa - wb) * uvs[tri.x] + wa * uvs[tri.y] + wb * uvs[tri.z];
              const vec2 shifted((uv.x * float(atlas.width) + float(sx)) / float(width),
                                 (uv.y * float(atlas.height) + float(sy)) / float(height));
              own = read(chain[size_t(k)], k, width, height, shifted) >= 1.0f - 1e-5f;
            }
          if (!own) {
            clean = k - 1;
            break;
          }
        }
    }
  }
  return clean;
}

// Measured at every padding from 2 to 13 and at 16, 20, 23 and 24: level 0 alone from 2 to 5
// (the default 3 among them), down to level 1 from 6, to 2 from 12, to 3 from 24: a padding of
// 3 x 2^k keeps levels 0 .. k free, one less does not. The default and both sides of two steps:
TEST(MipGutters, PaddingKeepsItsMipLevelsFreeOfNeighbouringCharts) {
  const Scene scene = charts_scene();
  for (const auto& [padding, levels] :
       {std::pair{3, 0}, std::pair{5, 0}, std::pair{6, 1}, std::pair{11, 1}, std::pair{12, 2}}) {
    size_t charts = 0;
    const int clean = clean_levels(scene, padding, charts);
    std::printf("padding %2d: %zu charts, free of other charts' light down to level %d\n",
                padding, charts, clean);
    EXPECT_EQ(clean, levels) << "padding " << padding;
  }
}

}  // namespace
}  // namespace lb
