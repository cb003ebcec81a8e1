// Links mtc::qos alone: a timing is validated and leases heartbeat x missed
// heartbeats, and the named presets are listed.
#include <chrono>
#include <iostream>

#include "mtc/qos/presets.hpp"

int main() {
  mtc::qos::Timing timing;
  timing.heartbeat = std::chrono::milliseconds(50);
  mtc::qos::validate(timing);
  const auto names = mtc::qos::preset_names();
  std::cout << "mtc::qos: " << names.size() << " presets, lease " << timing.lease().count()
            << " ms\n";
  return !names.empty() && timing.lease() == std::chrono::milliseconds(150) ? 0 : 1;
}
