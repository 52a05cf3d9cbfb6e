// CPU seconds of the bake's geometry preparation, stage by stage, on one scene (issue 16):
//
//   build/bench/geometry_stages build/level/l1000000.toml [--no-contact-cuts]
//
// Stages as the bake runs them: loading (parse, shapes, instances, validation), the Embree
// build, the illumination atlas (charts, unwrap, packing), the radiosity patches (crease
// split and refinement, contact cuts, coverage probes, grouping). Process CPU seconds (all
// threads; the Embree build is parallel), one line per stage, then the scene's sizes.

#include <cstdio>
#include <ctime>
#include <exception>
#include <string>

#include "bake/accel.h"
#include "bake/illumination/atlas.h"
#include "bake/io/scene_load.h"
#include "bake/radiosity/patches.h"

namespace {

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace lb;
  const bool contact_cuts = !(argc == 3 && std::string(argv[2]) == "--no-contact-cuts");
  if (argc != 2 && contact_cuts) {
    std::fprintf(stderr, "usage: %s SCENE [--no-contact-cuts]\n", argv[0]);
    return 2;
  }
  try {
    double clock = process_cpu_seconds();
    auto lap = [&clock](const char* stage) {
      const double now = process_cpu_seconds();
      std::printf("%-24s %8.3f CPU s\n", stage, now - clock);
      clock = now;
    };
    const Scene scene = load_scene(argv[1]).scene;
    lap("load");
    const Accel accel(scene);
    lap("embree");
    std::vector<bool> diffuse(scene.meshes.size());
    for (size_t m = 0; m < scene.meshes.size(); ++m)
      diffuse[m] = scene.materials[size_t(scene.meshes[m].material)].is_diffuse();
    const Atlas atlas = build_atlas(scene, diffuse, AtlasParams{});
    lap("atlas");
    const Patches patches = build_patches(scene, 0.0f, true, &accel, contact_cuts);
    lap("patches");
    std::printf("  %-22s %8.3f CPU s\n", "refine", patches.seconds.refine);
    std::printf("  %-22s %8.3f CPU s\n", "contact cuts", patches.seconds.cuts);
    std::printf("  %-22s %8.3f CPU s\n", "coverage", patches.seconds.coverage);
    std::printf("  %-22s %8.3f CPU s\n", "grouping", patches.seconds.grouping);
    std::printf("%zu meshes, %zu triangles, %zu patches of %g m, atlas %d x %d\n",
                scene.meshes.size(), triangle_count(scene), patches.patches.size(),
                double(patches.default_patch_size), atlas.width, atlas.height);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "geometry_stages: %s\n", e.what());
    return 1;
  }
  return 0;
}
