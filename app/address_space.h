#pragma once
// An address-space limit (`ulimit -v`, RLIMIT_AS) too small for a command is refused before any
// work: under one, the libraries a command maps (Embree, TBB, the image library, OpenGL's
// llvmpipe with LLVM) fail inside themselves, with std::bad_alloc thrown on a worker thread
// (abort) or a segfault, instead of an error naming the limit.

#include <CLI/CLI.hpp>

namespace lb::app {

// Makes `cmd` check, once its options are parsed, the address-space limit against what the
// command needs with its thread count (docs/stability.md, "Fault edges").
void add_address_space_check(CLI::App& cmd);

}  // namespace lb::app
