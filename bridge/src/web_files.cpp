#include "web_files.hpp"

namespace mtc::bridge::detail {

const WebFile* find_web_file(std::string_view name) noexcept {
  for (std::size_t i = 0; i < kWebFileCount; ++i) {
    if (kWebFiles[i].name == name) return &kWebFiles[i];
  }
  return nullptr;
}

}  // namespace mtc::bridge::detail
