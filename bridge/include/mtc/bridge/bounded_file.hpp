// Reading a whole file the user named (a Devices file, agent.cfg) without
// trusting it: a size limit checked while reading, so /dev/zero or a
// multi-gigabyte file ends in a clear error instead of std::bad_alloc, and
// a directory is named as such instead of reading as an empty file.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace mtc::bridge {

// The file's bytes, or nullopt with `error` saying why not, naming the
// file as `what` ("cannot open config file: No such file or directory",
// "config file is a directory", "config file is larger than 4096 bytes").
// Pipes and devices are read as far as the limit allows.
std::optional<std::string> read_bounded_file(const std::string& path, std::size_t limit,
                                             std::string_view what, std::string& error);

}  // namespace mtc::bridge
