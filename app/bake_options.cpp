#include "app/bake_options.h"

#include <type_traits>
#include <variant>

#include "app/cli_parse.h"
#include "bake/pipeline/bake_io.h"

namespace lb::app {

BakeSettingsRequest BakeCommandLine::request(std::optional<uint64_t> seed) const {
  BakeSettingsRequest request;
  if (!like.empty()) request.like = read_bake_settings(like);
  request.quality = quality;
  for (const auto& [setting, option] : options) {
    const bool given = option->count() > 0 || (texel_density && texel_density->count() > 0 &&
                                               std::string_view(setting->key) == "texel_size");
    if (given) request.given.push_back({setting, setting->get(values)});
  }
  if (seed) request.given.push_back({find_bake_setting("seed"), double(*seed)});
  if (directional)
    request.given.push_back({find_bake_setting("directional"), *directional ? 1.0 : 0.0});
  return request;
}

BakeParams resolve_bake_params(const Scene& scene, const BakeCommandLine& line,
                               std::optional<uint64_t> seed) {
  return lb::resolve_bake_params(scene, line.request(seed));
}

void add_bake_options(CLI::App& cmd, BakeCommandLine& line, const char* group, bool with_seed) {
  std::vector<CLI::Option*> level_settings;  // --quality excludes these
  CLI::Option* texel_size = nullptr;
  for (const BakeSetting& setting : bake_settings()) {
    if (!with_seed && std::string_view(setting.key) == "seed") continue;
    // The command's own --directional sets it (BakeCommandLine::directional).
    if (group && std::string_view(setting.key) == "directional") continue;
    CLI::Option* option = std::visit(
        [&](auto* target) -> CLI::Option* {
          using T = std::remove_pointer_t<decltype(target)>;
          if constexpr (std::is_same_v<T, bool>) {
            return cmd.add_flag(setting.option_name() + ",!" + setting.negative_option_name(),
                                *target,
                                std::string(setting.help) + (*target ? " (default: on)" : ""));
          } else {
            return cmd.add_option(setting.option_name(), *target, setting.help)
                ->check(CLI::Range(setting.min, setting.max));
          }
        },
        setting.field(line.values));
    option->capture_default_str()->group(group ? group : setting.group);
    line.options.emplace_back(&setting, option);
    if (setting.level_exclusive) level_settings.push_back(option);
    if (std::string_view(setting.key) == "texel_size") texel_size = option;
  }
  line.texel_density = add_texel_density_option(cmd, line.values.illumination)
                           ->group(group ? group : texel_size->get_group())
                           ->excludes(texel_size);
  CLI::Option* quality = add_quality_option(cmd, line.quality);
  for (CLI::Option* option : level_settings) quality->excludes(option);
  cmd.add_option("--like", line.like,
                 "Bake with the settings a previous bake recorded in BAKE_DIR/manifest.json "
                 "(options given as well win)")
      ->group(group ? group : "Bake");
}

}  // namespace lb::app
