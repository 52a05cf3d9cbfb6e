#pragma once
// The bake's settings on the command line: every entry of the settings table
// (bake/pipeline/bake_settings.h) as an option named after its key, with --quality and
// --like, for each subcommand that bakes (bake; snapshot, render, export and view when they
// bake first), so the same setting has the same name everywhere.

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bake/pipeline/bake_settings.h"

namespace lb::app {

struct BakeCommandLine {
  BakeParams values;               // what the options parse into
  std::optional<Quality> quality;  // --quality
  std::string like;                // --like BAKE_DIR
  std::vector<std::pair<const BakeSetting*, CLI::Option*>> options;
  CLI::Option* texel_density = nullptr;  // --texel-density, the inverse of --texel-size
  // Commands that bake as a side job read the map's band with their own --directional (and
  // --no-directional): given, it sets the `directional` setting of the bake they make too.
  std::optional<bool> directional;

  // After parsing: what the options ask for (reads --like's manifest; throws
  // std::runtime_error naming it when it cannot). `seed`: the command's own --seed, when
  // given (render, view: it seeds the bake too).
  BakeSettingsRequest request(std::optional<uint64_t> seed = std::nullopt) const;
};

// The heading of the bake's options in commands that bake only when given no bake directory.
inline constexpr const char* kBakeFirstGroup = "Bake (when no BAKE_DIR is given)";

// Adds the options to `cmd`. `group`: one heading for all of them (commands for which the bake
// is a side job), or nullptr for the table's own groups. `with_seed` false: the command's own
// --seed seeds the bake as well (render, view) and sets `values.seed` itself.
void add_bake_options(CLI::App& cmd, BakeCommandLine& line, const char* group, bool with_seed);

// The settings of the bake a command makes for `scene` (`seed`: the command's own --seed, when
// given; it seeds the bake too).
BakeParams resolve_bake_params(const Scene& scene, const BakeCommandLine& line,
                               std::optional<uint64_t> seed = std::nullopt);

}  // namespace lb::app
