#include "app/cli_parse.h"

#include <stdexcept>

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

}  // namespace lb::app
