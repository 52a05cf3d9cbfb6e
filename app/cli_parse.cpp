#include "app/cli_parse.h"

#include <cmath>
#include <stdexcept>

#include "app/commands.h"

namespace lb::app {

void parse_size(const std::string& text, int& width, int& height) {
  constexpr int kLargest = 16384;
  const auto x = text.find('x');
  try {
    if (x == std::string::npos) throw std::invalid_argument("");
    size_t used = 0;
    width = std::stoi(text.substr(0, x), &used);
    if (used != x) throw std::invalid_argument("");
    height = std::stoi(text.substr(x + 1), &used);
    if (used != text.size() - x - 1) throw std::invalid_argument("");
  } catch (const std::exception&) {
    throw std::invalid_argument("--size '" + text + "': expected WIDTHxHEIGHT, e.g. 1024x768");
  }
  if (width < 1 || height < 1 || width > kLargest || height > kLargest)
    throw std::invalid_argument("--size '" + text + "': each side must be in [1, 16384]");
}

int parse_samples_per_side(int spp) {
  const int side = int(std::lround(std::sqrt(double(spp))));
  if (spp <= 0 || side * side != spp)
    throw std::invalid_argument(
        "--spp: expected a square number of samples per pixel (1, 4, 9, 16, ...), got " +
        std::to_string(spp));
  return side;
}

ShardOption parse_shard(const std::string& text, int max_count) {
  ShardOption shard;
  const size_t slash = text.find('/');
  try {
    size_t used_i = 0, used_n = 0;
    if (slash == std::string::npos) throw std::invalid_argument(text);
    shard.index = std::stoi(text.substr(0, slash), &used_i);
    shard.count = std::stoi(text.substr(slash + 1), &used_n);
    if (used_i != slash || used_n != text.size() - slash - 1) throw std::invalid_argument(text);
  } catch (const std::exception&) {
    fail("--shard: expected INDEX/COUNT such as 0/4, got '" + text + "'");
  }
  if (!(shard.index >= 0 && shard.index < shard.count && shard.count <= max_count))
    fail("--shard " + text + ": needs 0 <= INDEX < COUNT <= " + std::to_string(max_count));
  return shard;
}

}  // namespace lb::app

namespace lb::app {

CLI::Option* add_texel_density_option(CLI::App& cmd, IlluminationParams& params) {
  return cmd
      .add_option_function<float>(
          "--texel-density",
          [&params](float density) { params.texel_size = density > 0.0f ? 1.0f / density : 0.0f; },
          "Lightmap texels per metre (0 = automatic: about 41 in a 4 x 4 x 2.5 m room)")
      ->check(CLI::Range(0.0f, 1e6f));
}

CLI::Option* add_quality_option(CLI::App& cmd, std::optional<Quality>& quality) {
  return cmd
      .add_option_function<std::string>(
          "--quality", [&quality](const std::string& name) { quality = parse_quality(name); },
          "Bake quality: draft, standard, high or final (default: the scene file's [bake] "
          "quality, else standard)")
      ->check([](const std::string& name) {
        try {
          parse_quality(name);
          return std::string();
        } catch (const std::invalid_argument& e) {
          return std::string(e.what());
        }
      });
}

}  // namespace lb::app
