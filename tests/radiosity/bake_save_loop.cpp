// A process that does nothing but save bakes, for the kill test in test_bake_destination.cpp:
// `bake_save_loop FIRST SECOND DIR` loads two bakes of make_room_with_mirror() (the test bakes
// them once, with two seeds), saves FIRST into DIR, prints "ready", then saves the two into DIR
// in turn, forever. The test kills it with SIGKILL at many moments and checks that DIR always
// loads. Loading instead of baking keeps each of the test's sixteen starts to milliseconds.

#include <cstdio>
#include <exception>

#include "bake/pipeline/bake_io.h"
#include "scenes.h"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: bake_save_loop FIRST SECOND DIR\n");
    return 2;
  }
  try {
    const lb::Scene scene = lb::test::make_room_with_mirror();
    const lb::BakeResult first = lb::load_bake(argv[1], scene);
    const lb::BakeResult second = lb::load_bake(argv[2], scene);
    lb::save_bake(argv[3], scene, first);
    std::printf("ready\n");
    std::fflush(stdout);
    for (unsigned long n = 1;; ++n) lb::save_bake(argv[3], scene, n % 2 ? second : first);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bake_save_loop: %s\n", e.what());
    return 1;
  }
}
