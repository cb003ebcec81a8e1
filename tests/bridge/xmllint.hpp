// xmllint against the official MTConnect XSDs (MTC_SCHEMA_DIR), for the
// tests that prove documents valid. A missing schema folder or xmllint makes
// those tests fail: validation is their point.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "mtc/bridge/schema_version.hpp"

namespace mtc::bridge::test {

struct Lint {
  int exit_code = -1;
  std::string output;
};

inline Lint xmllint(const std::string& body, const std::string& schema) {
  namespace fs = std::filesystem;
  static int counter = 0;
  const fs::path dir =
      fs::temp_directory_path() / ("mtc_bridge_schema_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path doc = dir / ("doc" + std::to_string(++counter) + ".xml");
  const fs::path out = dir / ("out" + std::to_string(counter) + ".txt");
  std::ofstream(doc, std::ios::binary) << body;
  const std::string cmd = std::string(MTC_XMLLINT) + " --noout --schema '" + schema + "' '" +
                          doc.string() + "' > '" + out.string() + "' 2>&1";
  Lint lint;
  // Test bodies run on one thread; nothing else touches the environment.
  const int rc = std::system(cmd.c_str());  // NOLINT(concurrency-mt-unsafe)
  lint.exit_code = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  std::ifstream in(out);
  std::ostringstream text;
  text << in.rdbuf();
  lint.output = text.str();
  std::error_code ignored;
  fs::remove(doc, ignored);
  fs::remove(out, ignored);
  fs::remove(dir, ignored);  // empty now: one per test process piled up in /tmp
  return lint;
}

// Path of the official XSD of one document kind ("MTConnectStreams").
inline std::string schema(const char* kind, SchemaVersion v) {
  return std::string(MTC_SCHEMA_DIR) + "/" + kind + "_" + std::string(to_string(v)) + "_1.0.xsd";
}

}  // namespace mtc::bridge::test
