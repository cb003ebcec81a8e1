// A benchmark's JSON summary, the same way from every executable: on stdout
// for a pipe, and into --out FILE for run.sh.
#pragma once

#include <fstream>
#include <iostream>
#include <string>

namespace mtc::bench {

// Prints `json` and, when `path` is not empty, writes it there too. Returns
// main()'s exit code: 1 (said on stderr) when the file could not be written.
inline int emit_json(const std::string& json, const std::string& path, const std::string& program) {
  std::cout << json;
  if (path.empty()) return 0;
  std::ofstream file(path);
  file << json;
  if (!file) {
    std::cerr << program << ": cannot write " << path << "\n";
    return 1;
  }
  return 0;
}

}  // namespace mtc::bench
