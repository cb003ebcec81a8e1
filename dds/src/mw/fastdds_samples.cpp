#include "fastdds_samples.hpp"

#include <algorithm>

#include "mtc/dds/detail/topics.hpp"

namespace mtc::dds::mw::fastdds {

namespace topics = detail::topics;

namespace {

template <typename Sample>
void fill_common(const ObservedValue& v, Sample& out) {
  out.device_uuid(v.device_uuid);
  out.data_item_id(v.data_item_id);
  out.interface_id(v.interface_id);
  out.sequence_number(v.sequence_number);
  out.heartbeat_group(v.heartbeat_group);
  out.source_time_ns(v.source_time_ns);
}

// The IDL enumerator of a known state, else the number as it stands.
template <typename IdlValue, typename Known>
IdlValue idl_state(const std::optional<Known>& known, const ObservedState& s) {
  return known ? topics::to_idl(*known) : static_cast<IdlValue>(s.raw());
}

}  // namespace

void to_idl(const ObservedValue& v, const detail::ParticipantKey& paired,
            idl::InteractionSample& out) {
  fill_common(v, out);
  if (v.service) out.service(topics::to_idl(*v.service));
  if (v.sub_type) out.sub_type(topics::to_idl(*v.sub_type));
  out.state(idl_state<idl::interaction_state::Value>(v.state.interaction(), v.state));
  out.paired_device_uuid(v.paired_device_uuid);
  out.paired_interface_id(v.paired_interface_id);
  std::copy(paired.begin(), paired.end(), out.paired_participant().begin());
}

void to_idl(const ObservedValue& v, const detail::ParticipantKey&, idl::InterfaceStateSample& out) {
  fill_common(v, out);
  out.state(idl_state<idl::interface_state::Value>(v.state.interface_state(), v.state));
}

void to_idl(const ObservedValue& v, const detail::ParticipantKey&, idl::DoorStateSample& out) {
  fill_common(v, out);
  out.state(idl_state<idl::door_state::Value>(v.state.door(), v.state));
}

void to_idl(const ObservedValue& v, const detail::ParticipantKey&, idl::ChuckStateSample& out) {
  fill_common(v, out);
  out.state(idl_state<idl::chuck_state::Value>(v.state.chuck(), v.state));
}

void to_idl(const ObservedHeartbeat& h, idl::Heartbeat& out) {
  out.device_uuid(h.device_uuid);
  out.group(h.group);
  out.period_ms(h.period_ms);
  out.lease_ms(h.lease_ms);
  out.beat(h.beat);
  out.request_changes(h.request_changes);
  out.response_changes(h.response_changes);
  out.interface_state_changes(h.interface_state_changes);
  out.door_state_changes(h.door_state_changes);
  out.chuck_state_changes(h.chuck_state_changes);
  out.interaction_changes().clear();
  for (const auto& c : h.interaction_changes) {
    idl::InteractionChanges entry;
    entry.service(topics::to_idl(c.service));
    entry.sub_type(topics::to_idl(c.sub_type));
    entry.changes(c.changes);
    out.interaction_changes().push_back(entry);
  }
  out.source_time_ns(h.source_time_ns);
}

void to_idl(const ObservedDevice& d, std::uint64_t sequence_number, std::int64_t source_time_ns,
            idl::DeviceDescription& out) {
  out.device_uuid(d.device_uuid);
  out.name(d.name);
  out.interfaces().clear();
  for (const auto& i : d.interfaces) {
    idl::InterfaceDescription di;
    di.id(i.id);
    di.name(i.name);
    di.interface_type(topics::to_idl(i.type));
    for (const auto& item : i.data_items) {
      idl::DataItemDescription dd;
      dd.id(item.id);
      dd.name(item.name);
      dd.type(item.type);
      dd.sub_type(item.sub_type);
      dd.category(item.category);
      di.data_items().push_back(std::move(dd));
    }
    out.interfaces().push_back(std::move(di));
  }
  out.sequence_number(sequence_number);
  out.source_time_ns(source_time_ns);
}

}  // namespace mtc::dds::mw::fastdds
