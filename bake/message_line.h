#pragma once
// Every error and warning is one line on stderr, whatever the file names in it hold: a newline
// or another control byte in a path would split it (and a reader that takes one line per
// error would see half of it).

#include <string>
#include <string_view>

namespace lb {

// `text` with each control byte written as an escape: \n, \r, \t, else \xNN.
std::string escape_control_bytes(std::string_view text);

// Prints "lightbake: KIND: TEXT" on stderr as one line (TEXT escaped as above).
void print_message(const char* kind, std::string_view text);

}  // namespace lb
