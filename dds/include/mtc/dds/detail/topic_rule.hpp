// Internal, vendor-neutral: the rule every backend's tap applies to an
// interaction value before handing it on, and the fuzz target with it
// (tests/fuzz/receive_path.hpp).
#pragma once

#include <cstddef>

#include "mtc/core/observation.hpp"

namespace mtc::dds::detail {

// The tap's topic rule for a decoded interaction value that arrived on the
// interaction topic of index `topic` (request topics first, one per service,
// then the response topics): false when its service and sub-type name
// another topic, and the tap refuses it. A value without a service or
// sub-type passes here; the peer checks report and drop it.
bool on_its_interaction_topic(const core::ObservedValue& value, std::size_t topic);

}  // namespace mtc::dds::detail
