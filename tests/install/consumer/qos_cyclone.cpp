// Links mtc::qos_cyclone alone: the state preset as Cyclone QoS is reliable
// and transient-local, as it is for Fast DDS.
#include <iostream>

#include "mtc/qos/cyclone_qos.hpp"
#include "mtc/qos/presets.hpp"

int main() {
  const auto qos = mtc::qos::cyclone_writer_qos(mtc::qos::state_topic());
  dds_reliability_kind_t reliability{};
  dds_durability_kind_t durability{};
  const bool ok = dds_qget_reliability(qos.get(), &reliability, nullptr) &&
                  dds_qget_durability(qos.get(), &durability) &&
                  reliability == DDS_RELIABILITY_RELIABLE &&
                  durability == DDS_DURABILITY_TRANSIENT_LOCAL;
  std::cout << "mtc::qos_cyclone: state writer " << (ok ? "reliable, transient-local" : "WRONG")
            << "\n";
  return ok ? 0 : 1;
}
