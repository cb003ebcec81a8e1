// Internal, Cyclone DDS backend (MTC_CYCLONE builds; issue 9 section 3,
// step 4): core values to and from the C structs idlc generates from the
// same IDL. Both halves keep the Fast DDS backend's rules (fastdds_samples.hpp
// and decode_sample): a state outside its vocabulary travels and arrives as
// its number, a service or sub-type outside its vocabulary arrives unset, an
// interface type outside its vocabulary reads MaterialHandler, a string is
// cut at its IDL bound. tests/dds/test_wire_samples_cyclone.cpp round-trips
// every topic type.
#pragma once

#include <cstdint>
#include <vector>

#include "mtc/dds/domain_observer.hpp"
#include "mtc/idl_cyclone/mtconnect_interfaces.h"
#include "wire.hpp"

namespace mtc::dds::mw::cyclone {

void to_c(const ObservedValue& v, const detail::ParticipantKey& paired,
          mtc_idl_InteractionSample& out);
void to_c(const ObservedValue& v, const detail::ParticipantKey& paired,
          mtc_idl_InterfaceStateSample& out);
void to_c(const ObservedValue& v, const detail::ParticipantKey& paired,
          mtc_idl_DoorStateSample& out);
void to_c(const ObservedValue& v, const detail::ParticipantKey& paired,
          mtc_idl_ChuckStateSample& out);

// The interaction sample's paired participant comes with it.
ObservedValue from_c(const mtc_idl_InteractionSample& s, detail::ParticipantKey* paired = nullptr);
ObservedValue from_c(const mtc_idl_InterfaceStateSample& s);
ObservedValue from_c(const mtc_idl_DoorStateSample& s);
ObservedValue from_c(const mtc_idl_ChuckStateSample& s);

// A heartbeat as a C sample whose sequence points into this object (not
// owned by Cyclone: _release false), so it must outlive every write of
// `sample`; neither copied nor moved, for the pointer's sake.
struct CycloneHeartbeat {
  CycloneHeartbeat() = default;
  ~CycloneHeartbeat() = default;
  CycloneHeartbeat(const CycloneHeartbeat&) = delete;
  CycloneHeartbeat& operator=(const CycloneHeartbeat&) = delete;
  CycloneHeartbeat(CycloneHeartbeat&&) = delete;
  CycloneHeartbeat& operator=(CycloneHeartbeat&&) = delete;
  mtc_idl_Heartbeat sample{};
  std::vector<mtc_idl_InteractionChanges> changes;
};
void to_c(const ObservedHeartbeat& h, CycloneHeartbeat& out);
ObservedHeartbeat from_c(const mtc_idl_Heartbeat& s);

// The same for an announcement: the interfaces' and their data items'
// sequences point into this object.
struct CycloneDevice {
  CycloneDevice() = default;
  ~CycloneDevice() = default;
  CycloneDevice(const CycloneDevice&) = delete;
  CycloneDevice& operator=(const CycloneDevice&) = delete;
  CycloneDevice(CycloneDevice&&) = delete;
  CycloneDevice& operator=(CycloneDevice&&) = delete;
  mtc_idl_DeviceDescription sample{};
  std::vector<mtc_idl_InterfaceDescription> interfaces;
  std::vector<std::vector<mtc_idl_DataItemDescription>> data_items;
};
void to_c(const ObservedDevice& d, std::uint64_t sequence_number, std::int64_t source_time_ns,
          CycloneDevice& out);
ObservedDevice from_c(const mtc_idl_DeviceDescription& s);

}  // namespace mtc::dds::mw::cyclone
