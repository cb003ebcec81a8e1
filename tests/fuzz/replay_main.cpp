// The main() of a fuzz target in every build: runs LLVMFuzzerTestOneInput
// once per file, so the ordinary suite replays the seed corpus and every
// input that once made a target crash (ctest label "replay"). libFuzzer
// builds (MTC_FUZZ=ON) link the same target with libFuzzer's main instead.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

namespace fs = std::filesystem;

void usage(std::ostream& out, const char* program) {
  out << "usage: " << program << " FILE|DIR...\n"
      << "Runs this fuzz target once on each FILE and on each file in each DIR\n"
      << "(sorted by name), as libFuzzer would, and prints how many it ran.\n"
      << "A broken invariant aborts with the file's name on stderr; no input\n"
      << "at all is an error (exit 1), a bad option a usage error (exit 2).\n";
}

std::vector<fs::path> inputs_of(const fs::path& path) {
  std::vector<fs::path> files;
  if (fs::is_directory(path)) {
    for (const auto& entry : fs::directory_iterator(path)) {
      if (entry.is_regular_file()) files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
  } else {
    files.push_back(path);
  }
  return files;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<fs::path> files;
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      usage(std::cout, argv[0]);
      return 0;
    }
    if (!arg.empty() && arg.front() == '-') {
      std::cerr << argv[0] << ": unknown option '" << arg << "'\n";
      usage(std::cerr, argv[0]);
      return 2;
    }
    if (!fs::exists(argv[i])) {
      std::cerr << argv[0] << ": no such file or directory: " << arg << "\n";
      return 2;
    }
    const auto found = inputs_of(argv[i]);
    files.insert(files.end(), found.begin(), found.end());
  }
  if (files.empty()) {
    std::cerr << argv[0] << ": no inputs to replay\n";
    usage(std::cerr, argv[0]);
    return 1;
  }
  for (const auto& file : files) {
    std::ifstream in(file, std::ios::binary);
    if (!in) {
      std::cerr << argv[0] << ": cannot read " << file << "\n";
      return 1;
    }
    const std::vector<char> bytes{std::istreambuf_iterator<char>(in),
                                  std::istreambuf_iterator<char>()};
    std::cerr << "replay: " << file.string() << " (" << bytes.size() << " bytes)\n";
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  }
  std::cout << "replayed " << files.size() << " inputs\n";
  return 0;
}
