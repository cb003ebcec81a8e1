// Limits of the Devices file loader, in a header of its own: AgentOptions
// holds them without the agent's header depending on the model's.
#pragma once

#include <cstddef>

namespace mtc::bridge {

// What a Devices file may demand of the loader. A file beyond these limits
// is a ModelError naming the file (and the line where it crosses them).
struct ModelLimits {
  // Bytes read at most; a larger file (or an endless one such as /dev/zero)
  // is refused before parsing. Real Devices files are a few hundred KiB.
  std::size_t max_file_bytes = std::size_t{32} << 20;
  // Elements nested at most, counting <MTConnectDevices> as 1. A Device
  // with components ten levels deep needs about 25; the checks and indexes
  // recurse per level, so this also bounds their stack.
  std::size_t max_depth = 64;
};

}  // namespace mtc::bridge
