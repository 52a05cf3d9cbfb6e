#include "bake/message_line.h"

#include <cstdio>

namespace lb {

std::string escape_control_bytes(std::string_view text) {
  std::string line;
  line.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte != 0x7f) {
      line += c;
    } else if (c == '\n') {
      line += "\\n";
    } else if (c == '\r') {
      line += "\\r";
    } else if (c == '\t') {
      line += "\\t";
    } else {
      char escape[5];
      std::snprintf(escape, sizeof escape, "\\x%02x", byte);
      line += escape;
    }
  }
  return line;
}

void print_message(const char* kind, std::string_view text) {
  std::fprintf(stderr, "lightbake: %s: %s\n", kind, escape_control_bytes(text).c_str());
}

}  // namespace lb
