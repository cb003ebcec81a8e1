// Links mtc::qos alone: a timing is validated and leases heartbeat x missed
// heartbeats, the named presets are listed, and the installed Fast DDS
// reading of a preset (fastdds_qos.hpp, apart from the neutral EndpointQos)
// gives a reliable writer.
#include <chrono>
#include <iostream>

#include "mtc/qos/fastdds_qos.hpp"
#include "mtc/qos/presets.hpp"

int main() {
  mtc::qos::Timing timing;
  timing.heartbeat = std::chrono::milliseconds(50);
  mtc::qos::validate(timing);
  const auto names = mtc::qos::preset_names();
  const bool reliable = mtc::qos::fastdds_writer_qos(mtc::qos::state_topic()).reliability().kind ==
                        eprosima::fastdds::dds::RELIABLE_RELIABILITY_QOS;
  std::cout << "mtc::qos: " << names.size() << " presets, lease " << timing.lease().count()
            << " ms, state writer " << (reliable ? "reliable" : "NOT reliable") << "\n";
  return !names.empty() && timing.lease() == std::chrono::milliseconds(150) && reliable ? 0 : 1;
}
