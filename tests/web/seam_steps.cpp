// seam_steps FILE.glb IMAGE.png MAX_RATIO SURFACE...
// The steps lightmap seams leave in a frame of FILE's first camera, wherever they project (a
// sphere's charts, a floor's UV islands, objects that touch), against each surface's own
// steps beside them. Each pixel centre is traced through FILE's meshes (the ray the frame's
// rasteriser samples there); a triangle's chart is its island in the lightmap UVs (TEXCOORD_1,
// as given_uvs.h finds islands). A seam pair is two neighbouring pixels (across or down) on
// triangles of different charts that share a corner and face the same way (within the
// stitcher's 30 degrees: bake/lightmap/seam_stitch.h), so silhouettes and creases are not
// seams. With L a pixel's mean level (8-bit, as displayed) and d the step from
// pixel a to its neighbour b across the seam, the seam's jump is |L(b) - L(a)|, and the
// surface's own steps beside it are the three pairs a - 4d .. a - d and the three b + d .. b +
// 4d (the pairs that touch a or b left out), all on a's and b's charts: on a curved surface they
// follow its gradient along the same direction. Per surface (a mesh's name; "across objects"
// for pairs on two meshes): the mean jump over the mean step beside it. A seam whose two sides
// agree under bilinear filtering steps like its neighbours (ratio ~1). Prints each surface;
// exits 1 when a named SURFACE has fewer than kMinPairs seam pairs or a ratio over MAX_RATIO
// (issue 36: "seam jumps in three.js screenshots no larger than 1.2x the interior gradient"),
// 2 on bad input. Used by the three.js check (run_threejs_check.sh).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bake/accel.h"
#include "bake/camera.h"
#include "bake/illumination/given_uvs.h"
#include "bake/io/image_io.h"
#include "bake/io/scene_load.h"
#include "bake/thin_lens_camera.h"

namespace {

constexpr size_t kMinPairs = 20;
constexpr int kBeside = 4;  // pixels each side the steps beside a seam reach

struct Surface {
  double jump = 0.0, beside = 0.0;
  size_t pairs = 0;
};

// Per mesh, per triangle, its chart (or -1 where the mesh has no lightmap UVs): the UV islands
// the loader's check of given UVs finds (bake/illumination/given_uvs.h), which in an exported
// file are the atlas's charts, padded apart.
std::vector<std::vector<int>> chart_labels(const lb::Scene& scene) {
  std::vector<std::vector<int>> labels(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const lb::Mesh& mesh = scene.meshes[m];
    if (mesh.lightmap_uvs.size() == mesh.positions.size())
      labels[m] = lb::check_given_uvs(mesh).island;
    else
      labels[m].assign(mesh.triangles.size(), -1);
  }
  return labels;
}

bool share_a_corner(const lb::Scene& scene, const lb::Hit& a, const lb::Hit& b, float tolerance) {
  const lb::Mesh& ma = scene.meshes[a.mesh];
  const lb::Mesh& mb = scene.meshes[b.mesh];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (glm::distance(ma.positions[ma.triangles[a.triangle][i]],
                        mb.positions[mb.triangles[b.triangle][j]]) <= tolerance)
        return true;
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: seam_steps FILE.glb IMAGE.png MAX_RATIO SURFACE...\n");
    return 2;
  }
  try {
    const lb::LoadResult loaded = lb::load_scene(argv[1]);
    const lb::Scene& scene = loaded.scene;
    const lb::Image image = lb::read_image(argv[2]);
    const double max_ratio = std::atof(argv[3]);
    const int width = image.width, height = image.height;
    const lb::Accel accel(scene);
    const lb::ThinLensCamera camera(lb::select_camera(scene, ""), width, height);

    std::vector<std::optional<lb::Hit>> hits(size_t(width) * size_t(height));
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        hits[size_t(y) * size_t(width) + size_t(x)] = accel.intersect(
            camera.generate(lb::vec2(float(x) + 0.5f, float(y) + 0.5f), lb::vec2(0.5f)));
    const std::vector<std::vector<int>> labels = chart_labels(scene);
    auto chart = [&](int x, int y) -> std::pair<int64_t, int64_t> {  // (mesh, chart) or -1
      if (x < 0 || y < 0 || x >= width || y >= height) return {-1, -1};
      const std::optional<lb::Hit>& h = hits[size_t(y) * size_t(width) + size_t(x)];
      if (!h || labels[h->mesh][h->triangle] < 0) return {-1, -1};
      return {int64_t(h->mesh), int64_t(labels[h->mesh][h->triangle])};
    };
    auto level = [&](int x, int y) {
      double sum = 0.0;
      for (int c = 0; c < 3; ++c) sum += std::lround(image.at(x, y, c) * 255.0f);
      return sum / 3.0;
    };
    const float tolerance = 1e-4f * accel.scene_scale();
    const float cos_limit = std::cos(glm::radians(30.0f));

    std::map<std::string, Surface> surfaces;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
          const int bx = x + dx, by = y + dy;
          const auto ca = chart(x, y), cb = chart(bx, by);
          if (ca.first < 0 || cb.first < 0 || ca == cb) continue;
          const lb::Hit& ha = *hits[size_t(y) * size_t(width) + size_t(x)];
          const lb::Hit& hb = *hits[size_t(by) * size_t(width) + size_t(bx)];
          if (glm::dot(ha.geometric_normal, hb.geometric_normal) < cos_limit ||
              !share_a_corner(scene, ha, hb, tolerance))
            continue;
          bool clear = true;  // the pixels beside it lie on the same two charts
          for (int k = 1; k <= kBeside && clear; ++k)
            clear = chart(x - k * dx, y - k * dy) == ca && chart(bx + k * dx, by + k * dy) == cb;
          if (!clear) continue;
          double beside = 0.0;
          auto step = [&](int px, int py, int sx, int sy) {  // |L(p + s) - L(p)|
            return std::abs(level(px + sx, py + sy) - level(px, py));
          };
          for (int k = 1; k < kBeside; ++k)
            beside += step(x - k * dx, y - k * dy, -dx, -dy) +
                      step(bx + k * dx, by + k * dy, dx, dy);
          const std::string name = ha.mesh == hb.mesh ? scene.meshes[ha.mesh].name
                                                       : std::string("across objects");
          Surface& s = surfaces[name];
          s.jump += std::abs(level(bx, by) - level(x, y));
          s.beside += beside / double(2 * (kBeside - 1));
          ++s.pairs;
        }

    int status = 0;
    for (const auto& [name, s] : surfaces) {
      const double ratio = s.beside > 0.0 ? s.jump / s.beside : (s.jump > 0.0 ? INFINITY : 1.0);
      const bool named = std::find(argv + 4, argv + argc, name) != argv + argc;
      const bool within = ratio <= max_ratio;
      if (named && !within) status = 1;
      std::printf("%s: %s: %zu seam pairs, jump %.3f levels, beside %.3f, ratio %.2f "
                  "(limit %.2f): %s\n",
                  argv[2], name.c_str(), s.pairs, s.jump / double(s.pairs),
                  s.beside / double(s.pairs), ratio, max_ratio,
                  !named ? "not checked" : (within ? "within" : "OVER"));
    }
    for (int i = 4; i < argc; ++i)
      if (surfaces[argv[i]].pairs < kMinPairs) {
        std::printf("%s: %s: %zu seam pairs, fewer than %zu: not measured\n", argv[2], argv[i],
                    surfaces[argv[i]].pairs, kMinPairs);
        status = 1;
      }
    return status;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "seam_steps: %s\n", e.what());
    return 2;
  }
}
