// Received samples as core values: the conversion every reader's listener
// applies to what a peer sent before handing it on. Plain functions of the
// sample's fields (no DDS entity involved), so tests and the fuzz target
// (tests/fuzz/fuzz_dds_samples.cpp) can feed them any value a peer may send:
// enum numbers outside the vocabulary, any string, any sequence number.
#pragma once

#include <cstddef>

#include "mtc/core/observation.hpp"
#include "mtc/dds/detail/topic_rule.hpp"
#include "mtc/idl/mtconnect_interfaces.h"

namespace mtc::dds::detail {

// A state outside its vocabulary stays distinguishable
// (ObservedState::in_vocabulary() false, raw() as sent); a service or
// subType outside its vocabulary is left unset.
core::ObservedValue decode_sample(const idl::InteractionSample& sample);
core::ObservedValue decode_sample(const idl::InterfaceStateSample& sample);
core::ObservedValue decode_sample(const idl::DoorStateSample& sample);
core::ObservedValue decode_sample(const idl::ChuckStateSample& sample);
// An entry of interaction_changes outside the vocabulary is left out.
core::ObservedHeartbeat decode_sample(const idl::Heartbeat& sample);
// An interface type outside the vocabulary reads MaterialHandler.
core::ObservedDevice decode_sample(const idl::DeviceDescription& sample);

}  // namespace mtc::dds::detail
