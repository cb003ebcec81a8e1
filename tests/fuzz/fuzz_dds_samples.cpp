// Fuzz target: what a peer's samples become once received. Each input is a
// run of operations, each one sample of one topic, given either field by
// field (any enum number, any string, any sequence number) or as the CDR
// bytes a peer would put on the wire (deserialised with the type support
// the readers register). Every sample goes through the decoding the
// readers' listeners apply (mtc::dds::detail::decode_sample), which must
// keep every field and keep a state outside the vocabulary distinguishable;
// then through what the runtime does next (receive_path.hpp: the tap's topic
// rule, the peer checks), whose verdicts must follow the stated rules; what
// goes on reaches an MTConnect agent as DomainObserver feeds it, whose
// documents must stay XML whatever the peers announced.
#include <fastdds/rtps/common/SerializedPayload.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "fuzz_support.hpp"
#include "mtc/bridge/mtconnect_agent.hpp"
#include "mtc/dds/detail/sample_decoding.hpp"
#include "mtc/dds/detail/topics.hpp"
#include "mtc/idl/mtconnect_interfacesPubSubTypes.h"
#include "mtc/idl/type_support.hpp"
#include "receive_path.hpp"

namespace {

namespace idl = mtc::idl;
namespace core = mtc::core;
namespace topics = mtc::dds::detail::topics;
using mtc::fuzz::require;

// Enumerators in the IDL of each enum: a number below is in the vocabulary.
constexpr std::uint32_t kInteractionStates = 6;
constexpr std::uint32_t kInterfaceStates = 3;
constexpr std::uint32_t kDoorStates = 4;  // chuck states alike
constexpr std::uint32_t kServices = 10;
constexpr std::uint32_t kSubTypes = 2;
constexpr std::uint32_t kInterfaceTypes = 4;

// Strings that make values meet the announcements they belong to.
constexpr const char* kWords[] = {
    "dev-a",           "dev-b",      "itf",     "item-1",   "item-2", "MATERIAL_LOAD",
    "INTERFACE_STATE", "DOOR_STATE", "REQUEST", "RESPONSE", "EVENT"};

std::string text(mtc::fuzz::ByteReader& in) {
  const std::uint8_t pick = in.byte();
  if (pick < 176) return kWords[pick % std::size(kWords)];
  return in.string(80);  // past the IDL bounds of 64 and 128 on purpose
}

// The enum number as sent, also one the vocabulary lacks.
template <typename Enum>
Enum number(mtc::fuzz::ByteReader& in) {
  const std::uint8_t pick = in.byte();
  return static_cast<Enum>(pick < 128 ? pick % 12 : in.integer<std::uint32_t>());
}

template <typename Sample>
void check_header(const Sample& s, const core::ObservedValue& v) {
  require(v.device_uuid == s.device_uuid().to_string(), "device_uuid changed");
  require(v.data_item_id == s.data_item_id().to_string(), "data_item_id changed");
  require(v.interface_id == s.interface_id().to_string(), "interface_id changed");
  require(v.sequence_number == s.sequence_number(), "sequence_number changed");
  require(v.heartbeat_group == s.heartbeat_group(), "heartbeat_group changed");
  require(v.source_time_ns == s.source_time_ns(), "source_time_ns changed");
  if constexpr (std::is_same_v<Sample, idl::InteractionSample>) {
    require(v.paired_device_uuid == s.paired_device_uuid().to_string(), "paired device changed");
    require(v.paired_interface_id == s.paired_interface_id().to_string(),
            "paired interface changed");
  }
}

// The state as decoded: known numbers map back to themselves, others stay
// as sent and read INVALID(<number>).
template <typename Known>
void check_state(const core::ObservedState& state, core::ItemKind kind, std::uint32_t raw,
                 std::uint32_t vocabulary, const Known& known) {
  require(state.kind() == kind, "the state has another item kind");
  require(state.in_vocabulary() == (raw < vocabulary), "vocabulary membership changed");
  if (known) {
    require(static_cast<std::uint32_t>(topics::to_idl(*known)) == raw, "a state changed");
  } else {
    require(static_cast<std::uint32_t>(state.raw()) == raw, "a foreign state changed");
    require(core::to_string(state).rfind("INVALID(", 0) == 0, "a foreign state reads valid");
  }
}

core::ObservedValue decoded(const idl::InteractionSample& s) {
  auto v = mtc::dds::detail::decode_sample(s);
  check_header(s, v);
  check_state(v.state, core::ItemKind::Interaction, s.state(), kInteractionStates,
              v.state.interaction());
  require(v.service.has_value() == (s.service() < kServices), "service membership changed");
  require(v.sub_type.has_value() == (s.sub_type() < kSubTypes), "subType membership changed");
  if (v.service) require(topics::to_idl(*v.service) == s.service(), "service changed");
  if (v.sub_type) require(topics::to_idl(*v.sub_type) == s.sub_type(), "subType changed");
  return v;
}
core::ObservedValue decoded(const idl::InterfaceStateSample& s) {
  auto v = mtc::dds::detail::decode_sample(s);
  check_header(s, v);
  check_state(v.state, core::ItemKind::InterfaceState, s.state(), kInterfaceStates,
              v.state.interface_state());
  return v;
}
core::ObservedValue decoded(const idl::DoorStateSample& s) {
  auto v = mtc::dds::detail::decode_sample(s);
  check_header(s, v);
  check_state(v.state, core::ItemKind::DoorState, s.state(), kDoorStates, v.state.door());
  return v;
}
core::ObservedValue decoded(const idl::ChuckStateSample& s) {
  auto v = mtc::dds::detail::decode_sample(s);
  check_header(s, v);
  check_state(v.state, core::ItemKind::ChuckState, s.state(), kDoorStates, v.state.chuck());
  return v;
}
core::ObservedDevice decoded(const idl::DeviceDescription& s) {
  auto d = mtc::dds::detail::decode_sample(s);
  require(d.device_uuid == s.device_uuid().to_string(), "device_uuid changed");
  require(d.name == s.name().to_string(), "name changed");
  require(d.interfaces.size() == s.interfaces().size(), "interfaces lost");
  for (std::size_t i = 0; i < d.interfaces.size(); ++i) {
    const auto& sent = s.interfaces()[i];
    const auto& got = d.interfaces[i];
    require(got.id == sent.id().to_string(), "an interface id changed");
    const auto raw = static_cast<std::uint32_t>(sent.interface_type());
    if (raw < kInterfaceTypes) {
      require(topics::to_idl(got.type) == sent.interface_type(), "an interface type changed");
    } else {
      require(got.type == core::InterfaceType::MaterialHandler, "a foreign type is not kept");
    }
    require(got.data_items.size() == sent.data_items().size(), "data items lost");
  }
  return d;
}

template <typename Sample>
void fill_header(Sample& s, mtc::fuzz::ByteReader& in) {
  s.device_uuid(text(in));
  s.data_item_id(text(in));
  s.interface_id(text(in));
  s.sequence_number(in.integer<std::uint64_t>());
  s.heartbeat_group(in.integer<std::uint8_t>() < 200 ? 0 : in.integer<std::uint32_t>());
  s.source_time_ns(in.integer<std::int64_t>());
}

idl::DeviceDescription device_from(mtc::fuzz::ByteReader& in) {
  idl::DeviceDescription d;
  d.device_uuid(text(in));
  d.name(text(in));
  const std::size_t interfaces = in.byte() % 4;
  for (std::size_t i = 0; i < interfaces; ++i) {
    idl::InterfaceDescription itf;
    itf.id(text(in));
    itf.name(text(in));
    itf.interface_type(number<idl::interface_types::InterfaceType>(in));
    const std::size_t items = in.byte() % 5;
    for (std::size_t j = 0; j < items; ++j) {
      idl::DataItemDescription item;
      item.id(text(in));
      item.name(text(in));
      item.type(text(in));
      item.sub_type(text(in));
      item.category(text(in));
      itf.data_items().push_back(item);
    }
    d.interfaces().push_back(itf);
  }
  d.sequence_number(in.integer<std::uint64_t>());
  d.source_time_ns(in.integer<std::int64_t>());
  return d;
}

// A sample from CDR bytes as a reader's type support deserialises them;
// false for bytes the type support rejects (the reader drops them).
template <typename PubSub>
bool from_wire(mtc::fuzz::ByteReader& in, typename PubSub::type& sample) {
  const std::string bytes = in.string();
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(bytes.size()));
  if (!bytes.empty()) std::memcpy(payload.data, bytes.data(), bytes.size());
  payload.length = static_cast<std::uint32_t>(bytes.size());
  idl::SpecKeyType<PubSub> type;
  return type.deserialize(&payload, &sample);
}

// One cell seen by one runtime: the receive path's state and the agent.
struct Receiver {
  mtc::fuzz::ReceivePath path;
  std::unique_ptr<mtc::bridge::MtconnectAgent> agent;
};

template <typename Sample, typename PubSub>
void value_op(mtc::fuzz::ByteReader& in, bool wire, Receiver& to) {
  Sample s;
  if (wire) {
    if (!from_wire<PubSub>(in, s)) return;
  } else {
    fill_header(s, in);
    if constexpr (std::is_same_v<Sample, idl::InteractionSample>) {
      s.service(number<idl::services::Service>(in));
      s.sub_type(number<idl::sub_types::SubType>(in));
      s.paired_device_uuid(text(in));
      s.paired_interface_id(text(in));
    }
    s.state(number<std::decay_t<decltype(s.state())>>(in));
  }
  // Which writer sent it, which local group's reader got it, and on which
  // interaction topic (one per service and side) it arrived.
  const std::uint8_t writer = in.byte() % mtc::fuzz::ReceivePath::kWriters;
  const std::size_t group = in.byte() % mtc::fuzz::ReceivePath::kGroups;
  const std::size_t topic = in.byte() % mtc::dds::detail::kInteractionTopicCount;
  const auto value = decoded(s);
  if (to.path.receive(writer, group, topic, value)) to.agent->add_value(value);
}

void run_op(mtc::fuzz::ByteReader& in, Receiver& to) {
  auto& agent = *to.agent;
  const std::uint8_t op = in.byte();
  const bool wire = (op & 0x80) != 0;
  switch (op % 8) {
    case 0: {
      idl::DeviceDescription d;
      if (wire) {
        if (!from_wire<idl::DeviceDescriptionPubSubType>(in, d)) return;
      } else {
        d = device_from(in);
      }
      agent.add_device(decoded(d));
      return;
    }
    case 1:
      return value_op<idl::InteractionSample, idl::InteractionSamplePubSubType>(in, wire, to);
    case 2:
      return value_op<idl::InterfaceStateSample, idl::InterfaceStateSamplePubSubType>(in, wire, to);
    case 3:
      return value_op<idl::DoorStateSample, idl::DoorStateSamplePubSubType>(in, wire, to);
    case 4:
      return value_op<idl::ChuckStateSample, idl::ChuckStateSamplePubSubType>(in, wire, to);
    case 5: {
      const std::string device = text(in);
      std::vector<std::string> items{text(in)};
      items.push_back(text(in));
      return agent.items_lost(device, items);
    }
    case 6:
      return agent.device_lost(text(in));
    default:
      return to.path.forget(in.byte() % mtc::fuzz::ReceivePath::kWriters);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mtc::fuzz::ByteReader in(data, size);
  mtc::bridge::AgentOptions options;  // a model from the announcements
  options.buffer_size = 64;
  options.instance_id = 1;
  Receiver to{{}, mtc::bridge::make_agent(options)};
  for (int ops = 0; ops < 64 && !in.empty(); ++ops) {
    run_op(in, to);
  }
  const auto& agent = to.agent;
  for (const char* target : {"/probe", "/current", "/sample?count=64"}) {
    const auto routed = agent->route("GET", target);
    require(routed.response.has_value(), "no answer", target);
    mtc::fuzz::require_xml_document(routed.response->body, target);
  }
  return 0;
}
