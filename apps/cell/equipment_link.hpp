// The Link of one station over the DDS Equipment runtime (mtc::dds): the
// station's device, its interfaces and services, on `options.domain_id`.
#pragma once

#include <memory>
#include <string>

#include "cell_plan.hpp"
#include "ports.hpp"
#include "stations.hpp"

namespace mtc::cell {

// Throws std::runtime_error (with the runtime's message) when the equipment
// cannot be created.
std::unique_ptr<Link> make_equipment_link(StationId id, const CellOptions& options);

// The station's DDS-Security identity: <options.security_dir>/<its device
// uuid>, or "" when the cell runs unsecured.
std::string security_dir_of(StationId id, const CellOptions& options);

}  // namespace mtc::cell
