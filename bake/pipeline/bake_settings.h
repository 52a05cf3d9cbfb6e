#pragma once
// Every bake setting in one table: its key in a scene file's `[bake]` table and in a bake's
// manifest, its command-line option (`--key` with '-' for '_'), its help, group and range.
// The command line of every subcommand that bakes, the scene-file loader, the manifest and the
// viewer's panel all read this table, so a setting added to BakeParams is one entry here.

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "bake/pipeline/bake.h"

namespace lb {

struct BakeSetting {
  using Field = std::variant<int*, uint64_t*, float*, double*, bool*>;

  const char* key;              // snake_case; the option is --key in kebab-case
  const char* group;            // heading in --help and in the viewer's panel
  const char* help;             // one line, with the unit
  double min = 0.0, max = 0.0;  // inclusive range (booleans: 0 and 1)
  Field (*field)(BakeParams&) = nullptr;
  // A quality level sets this setting (apply_quality). `level_exclusive`: the command line
  // refuses it together with --quality (it is the level's to choose); otherwise (the texel
  // size, which an exported asset may need as it is) a value given with a level wins.
  bool set_by_level = false;
  bool level_exclusive = false;

  bool is_boolean() const;
  bool is_integer() const;
  double get(const BakeParams& params) const;
  // What is wrong with `value` for this setting ("VALUE is outside [MIN, MAX]", "... is not a
  // whole number"), or "" when it fits.
  std::string check(double value) const;
  // Sets the setting from a number (booleans: 0 or 1); throws std::invalid_argument
  // "KEY: " + check(value) when it does not fit.
  void set(BakeParams& params, double value) const;
  std::string option_name() const;           // "--patch-size"
  std::string negative_option_name() const;  // booleans: "--no-caustic-filter"
};

std::span<const BakeSetting> bake_settings();
const BakeSetting* find_bake_setting(std::string_view key);  // nullptr when unknown

// A setting gone from the table whose one value then is what every bake does today:
// `origins_over_light` (false) and `centre_origin_max_angle` (0.05 rad), the ray origins being
// each light's own choice now (MeshBakeSettings::caustic_origins). A manifest or a scene file
// that gives it at that value reads as before; another value is refused, naming the key, since
// no setting reproduces it.
struct RetiredBakeSetting {
  const char* key;
  double value;  // the one accepted (a float setting: any double that rounds to its float)
  bool boolean;
  // "" when `value` is the accepted one, else what is wrong (one line, without the key).
  std::string check(double given) const;
};
const RetiredBakeSetting* find_retired_bake_setting(std::string_view key);  // nullptr: not one

// A value given for one setting.
struct GivenSetting {
  const BakeSetting* setting = nullptr;
  double value = 0.0;
};

// Where a bake's settings come from, lowest precedence first:
//   1. the defaults (the passes' own, = the standard level);
//   2. either a previous bake's settings (`like`, read from its manifest: a bake reproduced
//      from its directory), or the scene file's level and then the scene file's own keys
//      (Scene::bake_settings); a file's keys win over the file's level;
//   3. the command line's level (`quality`), then the command line's keys (`given`).
// A level sets the settings marked set_by_level, so a later level replaces earlier values of
// those; every other setting passes through it.
struct BakeSettingsRequest {
  std::optional<BakeParams> like;
  std::optional<Quality> quality;
  std::vector<GivenSetting> given;
};

// Sets the scene file's own `[bake]` keys (Scene::bake_settings) in `params`. Throws
// std::invalid_argument naming the file, place and key of one that is unknown or out of range.
void apply_scene_bake_settings(const Scene& scene, BakeParams& params);

// The settings to bake `scene` with. Throws std::invalid_argument naming the file, place and
// key of a scene-file setting that is unknown or out of range.
BakeParams resolve_bake_params(const Scene& scene, const BakeSettingsRequest& request);

}  // namespace lb
