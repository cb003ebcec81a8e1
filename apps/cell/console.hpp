// Line-oriented output shared by the station processes: each line is one
// write(2) to stdout, so lines of different processes never interleave
// mid-line in a terminal or a pipe.
#pragma once

#include <string>
#include <string_view>

namespace mtc::cell {

// "12:00:01.234  robot    | text"
void print_line(std::string_view station, std::string_view text);

// printf-style formatting into a std::string.
std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

}  // namespace mtc::cell
