#include "domain_tap.hpp"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "mtc/dds/detail/return_code.hpp"
#include "mtc/dds/detail/sample_decoding.hpp"
#include "mtc/dds/detail/topics.hpp"
#include "mtc/idl/mtconnect_interfacesPubSubTypes.h"
#include "mtc/idl/type_support.hpp"
#include "mtc/qos/fastdds_qos.hpp"
#include "mtc/qos/participant.hpp"
#include "mtc/qos/presets.hpp"

namespace mtc::dds::detail {

namespace {

// The sample's state as a core enum; a number outside the vocabulary is kept
// as sent, so that the runtime can tell it from every known state.
template <typename IdlValue>
ObservedState observed_state(ItemKind kind, IdlValue value) {
  if (const auto known = topics::from_idl(value)) return *known;
  return ObservedState::outside_vocabulary(kind, static_cast<std::int32_t>(value));
}

ObservedValue base(std::string device, std::string item, std::string iface, std::uint64_t seq,
                   std::uint32_t group, std::int64_t t) {
  ObservedValue v;
  v.device_uuid = std::move(device);
  v.data_item_id = std::move(item);
  v.interface_id = std::move(iface);
  v.sequence_number = seq;
  v.heartbeat_group = group;
  v.source_time_ns = t;
  v.reception_time_ns = topics::realtime_ns();
  return v;
}

ObservedValue observe(const idl::InteractionSample& s) {
  auto v =
      base(s.device_uuid().to_string(), s.data_item_id().to_string(), s.interface_id().to_string(),
           s.sequence_number(), s.heartbeat_group(), s.source_time_ns());
  v.service = topics::from_idl(s.service());
  v.sub_type = topics::from_idl(s.sub_type());
  v.state = observed_state(ItemKind::Interaction, s.state());
  v.paired_device_uuid = s.paired_device_uuid().to_string();
  v.paired_interface_id = s.paired_interface_id().to_string();
  return v;
}

// INTERFACE_STATE, DOOR_STATE and CHUCK_STATE samples differ only in the
// type of their state.
constexpr ItemKind kind_of(const idl::InterfaceStateSample&) {
  return ItemKind::InterfaceState;
}
constexpr ItemKind kind_of(const idl::DoorStateSample&) {
  return ItemKind::DoorState;
}
constexpr ItemKind kind_of(const idl::ChuckStateSample&) {
  return ItemKind::ChuckState;
}

template <typename StateSample>
ObservedValue observe(const StateSample& s) {
  auto v =
      base(s.device_uuid().to_string(), s.data_item_id().to_string(), s.interface_id().to_string(),
           s.sequence_number(), s.heartbeat_group(), s.source_time_ns());
  v.state = observed_state(kind_of(s), s.state());
  return v;
}

ObservedHeartbeat observe(const idl::Heartbeat& h) {
  ObservedHeartbeat o;
  o.device_uuid = h.device_uuid().to_string();
  o.group = h.group();
  o.period_ms = h.period_ms();
  o.lease_ms = h.lease_ms();
  o.beat = h.beat();
  o.request_changes = h.request_changes();
  o.response_changes = h.response_changes();
  o.interface_state_changes = h.interface_state_changes();
  o.door_state_changes = h.door_state_changes();
  o.chuck_state_changes = h.chuck_state_changes();
  for (const auto& c : h.interaction_changes()) {
    const auto service = topics::from_idl(c.service());
    const auto side = topics::from_idl(c.sub_type());
    // An entry outside the vocabulary names no topic this runtime reads.
    if (service && side) o.interaction_changes.push_back({*service, *side, c.changes()});
  }
  o.source_time_ns = h.source_time_ns();
  o.reception_time_ns = topics::realtime_ns();
  return o;
}

// Relaxed counters of taken samples, shared by a tap's listeners.
struct Counters {
  std::atomic<std::uint64_t> values{0};
  std::atomic<std::uint64_t> heartbeats{0};
};

// One listener per reader: copies samples and statuses into TapEvents.
// An interaction topic's listener knows its topic (`interaction`, an
// interaction_index): a sample of another service or side is a violation.
template <typename Sample>
class TapListener final : public fdds::DataReaderListener {
 public:
  TapListener(TopicKind kind, const TapSink& sink, Counters& counters,
              std::size_t interaction = kInteractionTopicCount)
      : kind_(kind), interaction_(interaction), sink_(sink), counters_(counters) {}

  void on_data_available(fdds::DataReader* reader) override {
    Sample sample;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&sample, &info) == detail::ReturnCode::RETCODE_OK) {
      if (info.valid_data) {
        emit(sample, info);
      } else if (info.instance_state != fdds::ALIVE_INSTANCE_STATE) {
        sink_(InstanceGoneEvent{kind_, to_handle(info.instance_handle),
                                info.instance_state == fdds::NOT_ALIVE_DISPOSED_INSTANCE_STATE,
                                to_handle(info.publication_handle)});
      }
    }
  }
  void on_liveliness_changed(fdds::DataReader*,
                             const fdds::LivelinessChangedStatus& status) override {
    if (status.alive_count_change != 0) {
      sink_(WriterLivelinessEvent{kind_, to_handle(status.last_publication_handle),
                                  status.alive_count_change > 0});
    }
  }
  // A writer that is deleted or unmatched never loses liveliness in 2.9:
  // report it as gone here.
  void on_subscription_matched(fdds::DataReader*,
                               const fdds::SubscriptionMatchedStatus& status) override {
    if (status.current_count_change < 0) {
      sink_(WriterLivelinessEvent{kind_, to_handle(status.last_publication_handle), false, true});
    }
  }
  void on_requested_deadline_missed(fdds::DataReader*,
                                    const fdds::RequestedDeadlineMissedStatus& status) override {
    sink_(DeadlineMissedEvent{kind_, to_handle(status.last_instance_handle)});
  }
  void on_requested_incompatible_qos(fdds::DataReader*,
                                     const fdds::RequestedIncompatibleQosStatus& status) override {
    sink_(IncompatibleQosEvent{kind_, std::to_string(status.last_policy_id)});
  }

 private:
  void emit(const Sample& s, const fdds::SampleInfo& info) {
    if constexpr (std::is_same_v<Sample, idl::DeviceDescription>) {
      sink_(DeviceEvent{to_handle(info.publication_handle), to_handle(info.instance_handle),
                        to_observed(s)});
    } else if constexpr (std::is_same_v<Sample, idl::Heartbeat>) {
      counters_.heartbeats.fetch_add(1, std::memory_order_relaxed);
      sink_(HeartbeatEvent{to_handle(info.publication_handle), to_handle(info.instance_handle),
                           observe(s)});
    } else {
      auto value = observe(s);
      if constexpr (std::is_same_v<Sample, idl::InteractionSample>) {
        // A service or sub-type outside the vocabulary is the runtime's
        // peer checks' to report (detail::PeerChecks).
        if (!on_its_interaction_topic(value, interaction_)) {
          sink_(ProtocolViolationEvent{interaction_, to_handle(info.publication_handle),
                                       std::move(value)});
          return;
        }
      }
      counters_.values.fetch_add(1, std::memory_order_relaxed);
      ValueEvent event{kind_,
                       to_handle(info.publication_handle),
                       to_handle(info.instance_handle),
                       std::move(value),
                       {}};
      if constexpr (std::is_same_v<Sample, idl::InteractionSample>) {
        std::copy(s.paired_participant().begin(), s.paired_participant().end(),
                  event.paired.begin());
      }
      sink_(std::move(event));
    }
  }

  TopicKind kind_;
  std::size_t interaction_;
  const TapSink& sink_;
  Counters& counters_;
};

template <typename PubSub>
std::string type_name() {
  PubSub t;
  return t.getName();
}

}  // namespace

Handle to_handle(const eprosima::fastrtps::rtps::InstanceHandle_t& h) noexcept {
  Handle out{};
  std::memcpy(out.data(), static_cast<const eprosima::fastrtps::rtps::octet*>(h.value), out.size());
  return out;
}

void deliver_through_transports() {
  qos::set_intraprocess_delivery(false);
}

ObservedDevice to_observed(const idl::DeviceDescription& d) {
  ObservedDevice out;
  out.device_uuid = d.device_uuid().to_string();
  out.name = d.name().to_string();
  for (const auto& i : d.interfaces()) {
    ObservedInterface oi;
    oi.id = i.id().to_string();
    oi.name = i.name().to_string();
    oi.type = topics::from_idl(i.interface_type()).value_or(core::InterfaceType::MaterialHandler);
    for (const auto& item : i.data_items()) {
      oi.data_items.push_back({item.id().to_string(), item.name().to_string(),
                               item.type().to_string(), item.sub_type().to_string(),
                               item.category().to_string()});
    }
    out.interfaces.push_back(std::move(oi));
  }
  return out;
}

ObservedValue decode_sample(const idl::InteractionSample& sample) {
  return observe(sample);
}
ObservedValue decode_sample(const idl::InterfaceStateSample& sample) {
  return observe(sample);
}
ObservedValue decode_sample(const idl::DoorStateSample& sample) {
  return observe(sample);
}
ObservedValue decode_sample(const idl::ChuckStateSample& sample) {
  return observe(sample);
}
ObservedHeartbeat decode_sample(const idl::Heartbeat& sample) {
  return observe(sample);
}
ObservedDevice decode_sample(const idl::DeviceDescription& sample) {
  return to_observed(sample);
}
namespace {

// Registers an IDL type (once per participant) and returns its name.
template <typename PubSub>
std::string registered(Participant& participant) {
  participant.register_type(idl::type_support<PubSub>());
  return type_name<PubSub>();
}

// Registers the IDL type of a topic and creates it (not the interaction
// topics: TopicSet::interaction).
std::unique_ptr<Topic> make_topic(Participant& participant, TopicKind kind,
                                  const qos::Timing& timing) {
  std::string type;
  switch (kind) {
    case TopicKind::Request:
    case TopicKind::Response:
      throw ConfigError(std::string("TopicSet: ") + topic_name(kind) + " is one topic per service");
    case TopicKind::InterfaceState:
      type = registered<idl::InterfaceStateSamplePubSubType>(participant);
      break;
    case TopicKind::DoorState:
      type = registered<idl::DoorStateSamplePubSubType>(participant);
      break;
    case TopicKind::ChuckState:
      type = registered<idl::ChuckStateSamplePubSubType>(participant);
      break;
    case TopicKind::DeviceDescription:
      type = registered<idl::DeviceDescriptionPubSubType>(participant);
      return std::make_unique<Topic>(participant, topic_name(kind), type,
                                     qos::fastdds_topic_qos(qos::device_description_topic(timing)));
    case TopicKind::Heartbeat:
      type = registered<idl::HeartbeatPubSubType>(participant);
      return std::make_unique<Topic>(participant, topic_name(kind), type,
                                     qos::fastdds_topic_qos(qos::heartbeat_topic(timing)));
  }
  return std::make_unique<Topic>(participant, topic_name(kind), type,
                                 qos::fastdds_topic_qos(qos::state_topic(timing)));
}

}  // namespace

Topic& TopicSet::get(TopicKind kind) {
  auto& slot = topics_[static_cast<std::size_t>(kind)];
  if (!slot) {
    slot = make_topic(participant_, kind, timing_);
  }
  return *slot;
}

Topic& TopicSet::interaction(std::size_t index) {
  auto& slot = interactions_.at(index);
  if (!slot) {
    slot = std::make_unique<Topic>(participant_, interaction_topic_name(index),
                                   registered<idl::InteractionSamplePubSubType>(participant_),
                                   qos::fastdds_topic_qos(qos::state_topic(timing_)));
  }
  return *slot;
}

struct DomainTap::Impl {
  TapSink sink;
  Counters counters;
  std::array<std::unique_ptr<fdds::DataReaderListener>, kTopicKindCount> listeners;
  std::array<std::unique_ptr<fdds::DataReaderListener>, kInteractionTopicCount>
      interaction_listeners;
  std::unique_ptr<Subscriber> subscriber;
  std::array<std::unique_ptr<Reader>, kTopicKindCount> readers;
  std::array<std::unique_ptr<Reader>, kInteractionTopicCount> interaction_readers;
};

namespace {

std::unique_ptr<fdds::DataReaderListener> make_listener(TopicKind kind, const TapSink& sink,
                                                        Counters& counters) {
  switch (kind) {
    case TopicKind::Request:
    case TopicKind::Response:
      return nullptr;  // one per service: see DomainTap::DomainTap
    case TopicKind::InterfaceState:
      return std::make_unique<TapListener<idl::InterfaceStateSample>>(kind, sink, counters);
    case TopicKind::DoorState:
      return std::make_unique<TapListener<idl::DoorStateSample>>(kind, sink, counters);
    case TopicKind::ChuckState:
      return std::make_unique<TapListener<idl::ChuckStateSample>>(kind, sink, counters);
    case TopicKind::DeviceDescription:
      return std::make_unique<TapListener<idl::DeviceDescription>>(kind, sink, counters);
    case TopicKind::Heartbeat:
      return std::make_unique<TapListener<idl::Heartbeat>>(kind, sink, counters);
  }
  return nullptr;
}

fdds::DataReaderQos reader_qos(TopicKind kind, const TapConfig& config) {
  switch (kind) {
    case TopicKind::DeviceDescription: {
      auto q = qos::fastdds_reader_qos(qos::device_description_topic(config.timing));
      qos::announcement_memory(q);
      return q;
    }
    case TopicKind::Heartbeat:
      return config.observer ? qos::fastdds_reader_qos(qos::heartbeat_observer_topic(config.timing))
                             : qos::fastdds_reader_qos(qos::heartbeat_topic(config.timing));
    default:
      return config.observer ? qos::fastdds_reader_qos(qos::state_observer_topic(config.timing))
                             : qos::fastdds_reader_qos(qos::state_topic(config.timing));
  }
}

}  // namespace

DomainTap::DomainTap(Participant& participant, TopicSet& topics, const TapConfig& config,
                     TapSink sink)
    : impl_(std::make_unique<Impl>()) {
  impl_->sink = std::move(sink);
  impl_->subscriber = std::make_unique<Subscriber>(participant, config.partitions);
  for (std::size_t i = 0; i < kTopicKindCount; ++i) {
    const auto kind = static_cast<TopicKind>(i);
    if (!config.topics[i] || kind == TopicKind::Request || kind == TopicKind::Response) {
      continue;
    }
    impl_->listeners[i] = make_listener(kind, impl_->sink, impl_->counters);
    impl_->readers[i] = std::make_unique<Reader>(
        *impl_->subscriber, topics.get(kind), reader_qos(kind, config), impl_->listeners[i].get());
  }
  for (std::size_t i = 0; i < kInteractionTopicCount; ++i) {
    const auto side = interaction_side(i);
    if (!config.topics[static_cast<std::size_t>(side)] || !config.interactions[i]) continue;
    impl_->interaction_listeners[i] = std::make_unique<TapListener<idl::InteractionSample>>(
        side, impl_->sink, impl_->counters, i);
    impl_->interaction_readers[i] =
        std::make_unique<Reader>(*impl_->subscriber, topics.interaction(i),
                                 reader_qos(side, config), impl_->interaction_listeners[i].get());
  }
}

TapCounts DomainTap::counts() const noexcept {
  return {impl_->counters.values.load(std::memory_order_relaxed),
          impl_->counters.heartbeats.load(std::memory_order_relaxed)};
}

std::size_t DomainTap::reannounce() {
  return impl_->subscriber->reannounce();
}

DomainTap::~DomainTap() {
  // Readers first (they reference listeners and topics), then the rest.
  for (auto& r : impl_->readers) {
    r.reset();
  }
  for (auto& r : impl_->interaction_readers) {
    r.reset();
  }
  impl_->subscriber.reset();
}

}  // namespace mtc::dds::detail
