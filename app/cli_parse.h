#pragma once
// Parsing of option values shared by several subcommands.

#include <string>

namespace lb::app {

// "WIDTHxHEIGHT" with both in [1, 16384]; throws std::invalid_argument quoting the text.
void parse_size(const std::string& text, int& width, int& height);

}  // namespace lb::app
