// Readable, stable names for value-parameterised tests. CTest names come from
// gtest's list, which shows each parameter as gtest prints it; a struct it
// cannot print comes out as a byte dump with pointers in it, so the CTest
// name changed with every build and `ctest -R` could not select the case.
#pragma once

#include <cctype>
#include <cstddef>
#include <ostream>
#include <string>
#include <string_view>

namespace mtc::test {

// The text with every character other than a letter or digit as '_', cut at
// 40 characters: safe in a test name and on one line of gtest's list.
inline std::string printable(std::string_view text) {
  std::string out;
  for (const char c : text.substr(0, 40)) {
    out += std::isalnum(static_cast<unsigned char>(c)) != 0 ? c : '_';
  }
  return out;
}

// "<index>_<printable text>": the index keeps names unique.
inline std::string param_name(std::size_t index, std::string_view text) {
  return std::to_string(index) + "_" + printable(text);
}

}  // namespace mtc::test
