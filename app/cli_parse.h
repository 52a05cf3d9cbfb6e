#pragma once
// Parsing of option values shared by several subcommands.

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "bake/illumination/illumination.h"
#include "bake/quality.h"

namespace lb::app {

// "WIDTHxHEIGHT" with both in [1, 16384]; throws std::invalid_argument quoting the text.
void parse_size(const std::string& text, int& width, int& height);

// `--spp N`: N a square (1, 4, 9, 16, ...); returns its side, HqParams::samples_per_side.
// Throws std::invalid_argument otherwise.
int parse_samples_per_side(int spp);

// `--shard INDEX/COUNT` with 0 <= INDEX < COUNT <= max_count; calls fail() (one line, exit 1)
// quoting the text otherwise.
struct ShardOption {
  int index = 0, count = 1;
};
ShardOption parse_shard(const std::string& text, int max_count);

}  // namespace lb::app

namespace lb::app {

// `--texel-density TEXELS_PER_M`: the lightmap's texel density (0 = the automatic rule of
// bake/illumination/atlas.h), stored as its inverse, params.texel_size in metres.
CLI::Option* add_texel_density_option(CLI::App& cmd, IlluminationParams& params);

// `--quality LEVEL` (draft, standard, high, final) for the bake a subcommand runs; unset, the
// scene file's own level applies, else standard (bake/pipeline/bake.h, choose_quality).
CLI::Option* add_quality_option(CLI::App& cmd, std::optional<Quality>& quality);

}  // namespace lb::app
