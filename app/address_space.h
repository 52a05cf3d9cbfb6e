#pragma once
// An address-space limit (`ulimit -v`, RLIMIT_AS) too small for a command is refused before any
// work: under one, the libraries a command maps (Embree, TBB, the image library, OpenGL's
// llvmpipe with LLVM) fail inside themselves, with std::bad_alloc thrown on a worker thread
// (abort) or a segfault, instead of an error naming the limit.

#include <CLI/CLI.hpp>
#include <string>

#include "bake/scene.h"

namespace lb::app {

// Makes `cmd` check, once its options are parsed, the address-space limit against what the
// command needs with its thread count (docs/stability.md, "Fault edges").
void add_address_space_check(CLI::App& cmd);

// Once the scene is loaded: the command's need grown by what its triangles beyond the measured
// room's map (a big level's mesh and BVH), refused before any work, naming the scene; without
// it, a level of 2 M triangles under a 1 GB limit failed in Embree's BVH build after 80 s.
void require_address_space_for(const Scene& scene);

// What to say for a std::bad_alloc, which names nothing: "ran out of memory DOING under the
// address-space limit (ulimit -v) of 977 MiB; raise the limit", or "ran out of memory DOING
// (N available)" without a limit. `doing`: "" or " while loading it".
std::string out_of_memory_text(const std::string& doing = "");

}  // namespace lb::app
