// Built instead of equipment_latency.cpp when mtc::dds is not part of the
// build: the raw series still run and the JSON says nothing was measured.
#include <iostream>

#include "equipment_latency.hpp"

namespace mtc::bench {

std::vector<Series> run_equipment_series(const EquipmentBenchOptions&) {
  std::cerr << "equipment latency: mtc::dds runtime not built, series skipped\n";
  return {};
}

int run_equipment_peer(int, bool) {
  return 1;
}

}  // namespace mtc::bench
