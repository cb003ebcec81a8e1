#include "cyclone_samples.hpp"

#include <algorithm>
#include <cstring>
#include <optional>
#include <string>

#include "mtc/dds/detail/topic_names.hpp"

namespace mtc::dds::mw::cyclone {

namespace {

// idlc numbers every enum from 0 in IDL order, as the core vocabulary is:
// the conversion is by position, checked at each end of every enum here.
static_assert(mtc_idl_interaction_state_UNAVAILABLE ==
                  static_cast<int>(core::InteractionState::Unavailable) &&
              mtc_idl_interaction_state_FAIL == static_cast<int>(core::InteractionState::Fail));
static_assert(mtc_idl_interface_state_UNAVAILABLE ==
                  static_cast<int>(core::InterfaceState::Unavailable) &&
              mtc_idl_interface_state_DISABLED == static_cast<int>(core::InterfaceState::Disabled));
static_assert(mtc_idl_door_state_UNAVAILABLE == static_cast<int>(core::DoorState::Unavailable) &&
              mtc_idl_door_state_CLOSED == static_cast<int>(core::DoorState::Closed));
static_assert(mtc_idl_chuck_state_UNAVAILABLE == static_cast<int>(core::ChuckState::Unavailable) &&
              mtc_idl_chuck_state_CLOSED == static_cast<int>(core::ChuckState::Closed));
static_assert(mtc_idl_services_MATERIAL_FEED == static_cast<int>(core::Service::MaterialFeed) &&
              mtc_idl_services_MATERIAL_LOAD == static_cast<int>(core::Service::MaterialLoad) &&
              mtc_idl_services_CLOSE_CHUCK == static_cast<int>(core::Service::CloseChuck));
static_assert(mtc_idl_sub_types_REQUEST == static_cast<int>(core::SubType::Request) &&
              mtc_idl_sub_types_RESPONSE == static_cast<int>(core::SubType::Response));
static_assert(mtc_idl_interface_types_BAR_FEEDER ==
                  static_cast<int>(core::InterfaceType::BarFeeder) &&
              mtc_idl_interface_types_CHUCK == static_cast<int>(core::InterfaceType::Chuck));

// A core enumerator as the C enum of the same position.
template <typename C, typename Core>
C c_enum(Core v) {
  return static_cast<C>(static_cast<int>(v));
}

// A received C enum as the core enumerator, when within `last`.
template <typename Core, typename C>
std::optional<Core> core_enum(C v, Core last) {
  const auto i = static_cast<long long>(v);
  if (i < 0 || i > static_cast<long long>(last)) return std::nullopt;
  return static_cast<Core>(i);
}

// Cut at the bound (N - 1 characters) and always terminated.
template <std::size_t N>
void put(char (&to)[N], const std::string& from) {
  const auto n = std::min(from.size(), N - 1);
  std::memcpy(to, from.data(), n);
  std::memset(to + n, 0, N - n);
}

// Up to the first NUL, never past the array (a peer need not terminate).
template <std::size_t N>
std::string get(const char (&from)[N]) {
  return std::string(from, ::strnlen(from, N));
}

template <typename Sample>
void put_common(const ObservedValue& v, Sample& out) {
  put(out.device_uuid, v.device_uuid);
  put(out.data_item_id, v.data_item_id);
  put(out.interface_id, v.interface_id);
  out.sequence_number = v.sequence_number;
  out.heartbeat_group = v.heartbeat_group;
  out.source_time_ns = v.source_time_ns;
}

template <typename Sample>
ObservedValue get_common(const Sample& s) {
  ObservedValue v;
  v.device_uuid = get(s.device_uuid);
  v.data_item_id = get(s.data_item_id);
  v.interface_id = get(s.interface_id);
  v.sequence_number = s.sequence_number;
  v.heartbeat_group = s.heartbeat_group;
  v.source_time_ns = s.source_time_ns;
  v.reception_time_ns = detail::topics::realtime_ns();
  return v;
}

// A known state by position, else the number as it stands.
template <typename C, typename Known>
C c_state(const std::optional<Known>& known, const ObservedState& s) {
  return known ? c_enum<C>(*known) : static_cast<C>(s.raw());
}

template <typename Core, typename C>
ObservedState observed(core::ItemKind kind, C v, Core last) {
  if (const auto known = core_enum(v, last)) return *known;
  return ObservedState::outside_vocabulary(kind, static_cast<std::int32_t>(v));
}

}  // namespace

void to_c(const ObservedValue& v, const detail::ParticipantKey& paired,
          mtc_idl_InteractionSample& out) {
  put_common(v, out);
  out.service = c_enum<mtc_idl_services_Service>(v.service.value_or(core::Service::MaterialFeed));
  out.sub_type = c_enum<mtc_idl_sub_types_SubType>(v.sub_type.value_or(core::SubType::Request));
  out.state = c_state<mtc_idl_interaction_state_Value>(v.state.interaction(), v.state);
  put(out.paired_device_uuid, v.paired_device_uuid);
  put(out.paired_interface_id, v.paired_interface_id);
  std::copy(paired.begin(), paired.end(), std::begin(out.paired_participant));
}

void to_c(const ObservedValue& v, const detail::ParticipantKey&,
          mtc_idl_InterfaceStateSample& out) {
  put_common(v, out);
  out.state = c_state<mtc_idl_interface_state_Value>(v.state.interface_state(), v.state);
}

void to_c(const ObservedValue& v, const detail::ParticipantKey&, mtc_idl_DoorStateSample& out) {
  put_common(v, out);
  out.state = c_state<mtc_idl_door_state_Value>(v.state.door(), v.state);
}

void to_c(const ObservedValue& v, const detail::ParticipantKey&, mtc_idl_ChuckStateSample& out) {
  put_common(v, out);
  out.state = c_state<mtc_idl_chuck_state_Value>(v.state.chuck(), v.state);
}

ObservedValue from_c(const mtc_idl_InteractionSample& s, detail::ParticipantKey* paired) {
  auto v = get_common(s);
  v.service = core_enum(s.service, core::Service::CloseChuck);
  v.sub_type = core_enum(s.sub_type, core::SubType::Response);
  v.state = observed(core::ItemKind::Interaction, s.state, core::InteractionState::Fail);
  v.paired_device_uuid = get(s.paired_device_uuid);
  v.paired_interface_id = get(s.paired_interface_id);
  if (paired) {
    std::copy(std::begin(s.paired_participant), std::end(s.paired_participant), paired->begin());
  }
  return v;
}

ObservedValue from_c(const mtc_idl_InterfaceStateSample& s) {
  auto v = get_common(s);
  v.state = observed(core::ItemKind::InterfaceState, s.state, core::InterfaceState::Disabled);
  return v;
}

ObservedValue from_c(const mtc_idl_DoorStateSample& s) {
  auto v = get_common(s);
  v.state = observed(core::ItemKind::DoorState, s.state, core::DoorState::Closed);
  return v;
}

ObservedValue from_c(const mtc_idl_ChuckStateSample& s) {
  auto v = get_common(s);
  v.state = observed(core::ItemKind::ChuckState, s.state, core::ChuckState::Closed);
  return v;
}

void to_c(const ObservedHeartbeat& h, CycloneHeartbeat& out) {
  auto& s = out.sample;
  put(s.device_uuid, h.device_uuid);
  s.group = h.group;
  s.period_ms = h.period_ms;
  s.lease_ms = h.lease_ms;
  s.beat = h.beat;
  s.request_changes = h.request_changes;
  s.response_changes = h.response_changes;
  s.interface_state_changes = h.interface_state_changes;
  s.door_state_changes = h.door_state_changes;
  s.chuck_state_changes = h.chuck_state_changes;
  s.source_time_ns = h.source_time_ns;
  out.changes.clear();
  for (const auto& c : h.interaction_changes) {
    out.changes.push_back({c_enum<mtc_idl_services_Service>(c.service),
                           c_enum<mtc_idl_sub_types_SubType>(c.sub_type), c.changes});
  }
  const auto n = static_cast<std::uint32_t>(out.changes.size());
  s.interaction_changes = {n, n, out.changes.data(), false};
}

ObservedHeartbeat from_c(const mtc_idl_Heartbeat& s) {
  ObservedHeartbeat h;
  h.device_uuid = get(s.device_uuid);
  h.group = s.group;
  h.period_ms = s.period_ms;
  h.lease_ms = s.lease_ms;
  h.beat = s.beat;
  h.request_changes = s.request_changes;
  h.response_changes = s.response_changes;
  h.interface_state_changes = s.interface_state_changes;
  h.door_state_changes = s.door_state_changes;
  h.chuck_state_changes = s.chuck_state_changes;
  for (std::uint32_t i = 0; i < s.interaction_changes._length; ++i) {
    const auto& c = s.interaction_changes._buffer[i];
    const auto service = core_enum(c.service, core::Service::CloseChuck);
    const auto side = core_enum(c.sub_type, core::SubType::Response);
    // An entry outside the vocabulary names no topic this runtime reads.
    if (service && side) h.interaction_changes.push_back({*service, *side, c.changes});
  }
  h.source_time_ns = s.source_time_ns;
  h.reception_time_ns = detail::topics::realtime_ns();
  return h;
}

void to_c(const ObservedDevice& d, std::uint64_t sequence_number, std::int64_t source_time_ns,
          CycloneDevice& out) {
  auto& s = out.sample;
  put(s.device_uuid, d.device_uuid);
  put(s.name, d.name);
  s.sequence_number = sequence_number;
  s.source_time_ns = source_time_ns;
  out.interfaces.assign(d.interfaces.size(), mtc_idl_InterfaceDescription{});
  out.data_items.assign(d.interfaces.size(), {});
  for (std::size_t i = 0; i < d.interfaces.size(); ++i) {
    const auto& from = d.interfaces[i];
    auto& to = out.interfaces[i];
    put(to.id, from.id);
    put(to.name, from.name);
    to.interface_type = c_enum<mtc_idl_interface_types_InterfaceType>(from.type);
    auto& items = out.data_items[i];
    items.assign(from.data_items.size(), mtc_idl_DataItemDescription{});
    for (std::size_t k = 0; k < items.size(); ++k) {
      put(items[k].id, from.data_items[k].id);
      put(items[k].name, from.data_items[k].name);
      put(items[k].type, from.data_items[k].type);
      put(items[k].sub_type, from.data_items[k].sub_type);
      put(items[k].category, from.data_items[k].category);
    }
    const auto n = static_cast<std::uint32_t>(items.size());
    to.data_items = {n, n, items.data(), false};
  }
  const auto n = static_cast<std::uint32_t>(out.interfaces.size());
  s.interfaces = {n, n, out.interfaces.data(), false};
}

ObservedDevice from_c(const mtc_idl_DeviceDescription& s) {
  ObservedDevice d;
  d.device_uuid = get(s.device_uuid);
  d.name = get(s.name);
  for (std::uint32_t i = 0; i < s.interfaces._length; ++i) {
    const auto& from = s.interfaces._buffer[i];
    ObservedInterface itf;
    itf.id = get(from.id);
    itf.name = get(from.name);
    itf.type = core_enum(from.interface_type, core::InterfaceType::Chuck)
                   .value_or(core::InterfaceType::MaterialHandler);
    for (std::uint32_t k = 0; k < from.data_items._length; ++k) {
      const auto& item = from.data_items._buffer[k];
      itf.data_items.push_back(
          {get(item.id), get(item.name), get(item.type), get(item.sub_type), get(item.category)});
    }
    d.interfaces.push_back(std::move(itf));
  }
  return d;
}

}  // namespace mtc::dds::mw::cyclone
