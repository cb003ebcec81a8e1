// A throw-away PKI for the security tests, made by the project's own
// scripts/security/make-pki.sh (the script under test as much as the
// runtime) in a temporary directory, plus the broken variants the tests need:
// permissions signed by another CA, an edited governance, an expired identity.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "child_process.hpp"

namespace mtc::security_test {

namespace fs = std::filesystem;

// The test cell: cnc requests MATERIAL_LOAD and MATERIAL_UNLOAD from robot,
// which provides MATERIAL_LOAD only; intruder is a valid device identity
// that provides nothing; watcher is read-only.
inline constexpr const char* kCellDescription =
    "device sec-cnc requests=material_load,material_unload reads=sec-robot\n"
    "device sec-robot provides=material_load reads=sec-cnc\n"
    "device sec-intruder requests=open_door reads=*\n"
    "observer sec-watcher\n";

inline std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_text(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary | std::ios::trunc) << text;
}

// Runs make-pki.sh; throws with its output on error.
inline void make_pki(const fs::path& out, const std::vector<std::string>& extra = {}) {
  const fs::path cell = out.string() + ".cell.txt";
  write_text(cell, kCellDescription);
  std::vector<std::string> argv = {std::string(MTC_SOURCE_DIR) + "/scripts/security/make-pki.sh",
                                   "--cell", cell.string(), "--out", out.string()};
  argv.insert(argv.end(), extra.begin(), extra.end());
  test::ChildProcess pki(argv);
  if (pki.wait_exit(std::chrono::seconds(120)) != std::optional<int>(0)) {
    throw std::runtime_error("make-pki.sh failed:\n" + pki.transcript());
  }
}

// One PKI per test binary (key generation costs seconds on a busy machine).
class Pki {
 public:
  static Pki& get() {
    static Pki pki;
    return pki;
  }
  Pki(const Pki&) = delete;  // the one instance owns the directory
  Pki& operator=(const Pki&) = delete;
  std::string dir(const std::string& identity) const { return (root_ / "a" / identity).string(); }
  const fs::path& root() const { return root_; }

  // A copy of `identity`'s directory under `name`, for breaking it.
  std::string copy_of(const std::string& identity, const std::string& name) const {
    const fs::path to = root_ / name;
    fs::remove_all(to);
    fs::copy(dir(identity), to);
    return to.string();
  }
  // The same cell signed by another CA (b) and with expired identities
  // (expired, same CA as a).
  std::string other_ca_dir(const std::string& identity) {
    if (!fs::exists(root_ / "b")) make_pki(root_ / "b");
    return (root_ / "b" / identity).string();
  }
  std::string expired_dir(const std::string& identity) {
    if (!fs::exists(root_ / "expired")) {
      make_pki(root_ / "expired", {"--ca", (root_ / "a" / "ca").string(), "--not-before",
                                   "20200101000000Z", "--not-after", "20200102000000Z"});
    }
    return (root_ / "expired" / identity).string();
  }

 private:
  Pki() {
    char pattern[] = "/tmp/mtc-security-XXXXXX";
    const char* made = ::mkdtemp(pattern);
    if (made == nullptr) throw std::runtime_error("mkdtemp failed");
    root_ = made;
    make_pki(root_ / "a");
  }
  ~Pki() {
    std::error_code ignored;
    fs::remove_all(root_, ignored);
  }
  fs::path root_;
};

}  // namespace mtc::security_test
