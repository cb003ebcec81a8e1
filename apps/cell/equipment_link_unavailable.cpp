// Built instead of equipment_link.cpp while the DDS runtime is not part of
// the build: the cell can still run in memory (--local).
#include <stdexcept>

#include "equipment_link.hpp"

namespace mtc::cell {

std::unique_ptr<Link> make_equipment_link(StationId, const CellOptions&) {
  throw std::runtime_error("this build has no DDS Equipment runtime; run with --local");
}

}  // namespace mtc::cell
