#pragma once
// `--threads N`, the one thread-count option of every subcommand that does parallel work.

#include <CLI/CLI.hpp>

namespace lb::app {

// Adds `--threads N` to `cmd`: at most N threads work at once (0, the default: all cores).
// Set through TBB's global_control, which the bake, both renderers and Embree's BVH builds all
// run on; for OSMesa's llvmpipe it also sets LP_NUM_THREADS unless the environment has it.
// Results have the same bits whatever N (tests/integration/test_cli_threads.cpp).
CLI::Option* add_threads_option(CLI::App& cmd);

}  // namespace lb::app
