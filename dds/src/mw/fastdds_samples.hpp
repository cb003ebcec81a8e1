// Internal, Fast DDS backend: core values to the fastddsgen types, the
// write-side half of the conversion whose read side is decode_sample
// (mtc/dds/detail/sample_decoding.hpp). A round trip through both gives the
// value back (tests/dds/test_wire_samples.cpp).
#pragma once

#include <cstdint>

#include "mtc/dds/domain_observer.hpp"
#include "mtc/idl/mtconnect_interfaces.h"
#include "wire.hpp"

namespace mtc::dds::mw::fastdds {

// Each fills every field of `out` that the value carries (see
// mw::ValueWriter): `paired` only matters for an interaction sample. A
// state outside its vocabulary (which the runtime never writes, but a test
// peer may) is sent as its raw number.
void to_idl(const ObservedValue& v, const detail::ParticipantKey& paired,
            idl::InteractionSample& out);
void to_idl(const ObservedValue& v, const detail::ParticipantKey& paired,
            idl::InterfaceStateSample& out);
void to_idl(const ObservedValue& v, const detail::ParticipantKey& paired,
            idl::DoorStateSample& out);
void to_idl(const ObservedValue& v, const detail::ParticipantKey& paired,
            idl::ChuckStateSample& out);
void to_idl(const ObservedHeartbeat& h, idl::Heartbeat& out);
void to_idl(const ObservedDevice& d, std::uint64_t sequence_number, std::int64_t source_time_ns,
            idl::DeviceDescription& out);

}  // namespace mtc::dds::mw::fastdds
