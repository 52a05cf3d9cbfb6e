// A process that does nothing but save bakes, for the kill test in test_bake_destination.cpp:
// `bake_save_loop DIR` bakes make_room_with_mirror() twice (two seeds), then saves the two
// bakes into DIR in turn, forever, printing "ready" once DIR holds a whole bake. The test kills
// it with SIGKILL at many moments and checks that DIR always loads.

#include <cstdio>
#include <exception>

#include "bake/pipeline/bake.h"
#include "bake/pipeline/bake_io.h"
#include "scenes.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: bake_save_loop DIR\n");
    return 2;
  }
  try {
    const lb::Scene scene = lb::test::make_room_with_mirror();
    lb::BakeParams params;
    params.illumination.rays_per_zone_side = 16;
    params.radiosity.ray_budget = 50'000;
    const lb::BakeResult first = lb::bake_scene(scene, params);
    params.seed += 1;
    const lb::BakeResult second = lb::bake_scene(scene, params);
    lb::save_bake(argv[1], scene, first);
    std::printf("ready\n");
    std::fflush(stdout);
    for (unsigned long n = 1;; ++n) lb::save_bake(argv[1], scene, n % 2 ? second : first);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bake_save_loop: %s\n", e.what());
    return 1;
  }
}
