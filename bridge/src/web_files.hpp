// The live page's files (bridge/web/), compiled into the library at build
// time (cmake/embed_files.cmake writes web_files_data.cpp), so an installed
// bridge serves them without looking anything up on disk. Internal to
// mtc_bridge.
#pragma once

#include <cstddef>
#include <string_view>

namespace mtc::bridge::detail {

struct WebFile {
  std::string_view name;          // "app.js": served at /web/app.js
  std::string_view content_type;  // from the name's extension
  std::string_view body;
};

// The page served at `/` to browsers.
inline constexpr std::string_view kPageFile = "index.html";

// The file of that name, or nullptr.
const WebFile* find_web_file(std::string_view name) noexcept;

// Defined in the generated web_files_data.cpp.
extern const WebFile kWebFiles[];
extern const std::size_t kWebFileCount;

}  // namespace mtc::bridge::detail
