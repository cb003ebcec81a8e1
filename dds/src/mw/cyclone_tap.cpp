// The Cyclone DDS backend's tap: one subscriber, a reader per topic read,
// and a listener per reader whose callbacks (Cyclone's threads) turn every
// sample and status into the same TapEvents as the Fast DDS tap
// (domain_tap.cpp) and only hand them to the sink.
//
// Handles: a writer is named by its GUID, which a sample's publication
// handle (a local id) is turned into with dds_get_matched_publication_data,
// cached per handle from the match on (an unmatched writer can no longer be
// asked). An instance is named by its local instance handle, unique in the
// process and stable while the reader holds the instance: the runtime only
// compares instances of one tap.
#include <algorithm>
#include <array>
#include <atomic>
#include <mutex>
#include <type_traits>
#include <unordered_map>

#include "cyclone_backend.hpp"
#include "cyclone_entities.hpp"
#include "cyclone_samples.hpp"
#include "mtc/qos/cyclone_qos.hpp"
#include "mtc/qos/presets.hpp"

namespace mtc::dds::mw {

namespace {

using cyclone::Entity;
using detail::Handle;

Handle instance_handle(dds_instance_handle_t ih) noexcept {
  Handle out{};
  for (std::size_t i = 0; i < sizeof ih; ++i) {
    out[out.size() - 1 - i] = static_cast<std::uint8_t>(ih >> (8 * i));
  }
  return out;
}

struct Counters {
  std::atomic<std::uint64_t> values{0};
  std::atomic<std::uint64_t> heartbeats{0};
};

// What every reader's listener shares: where events go, and the counters.
struct TapShared {
  TapSink sink;
  Counters counters;
};

// The listener of one reader. Cyclone calls one entity's listener from one
// thread at a time, but the GUID cache is also read by status callbacks
// that Cyclone may run on another thread than data: it has a lock.
class ReaderTap {
 public:
  ReaderTap(TopicKind kind, std::size_t interaction, TapShared& shared)
      : kind_(kind), interaction_(interaction), shared_(shared) {}
  virtual ~ReaderTap() = default;
  ReaderTap(const ReaderTap&) = delete;
  ReaderTap& operator=(const ReaderTap&) = delete;
  ReaderTap(ReaderTap&&) = delete;
  ReaderTap& operator=(ReaderTap&&) = delete;

  virtual void take_all(dds_entity_t reader) = 0;
  void on_matched(dds_entity_t reader, const dds_subscription_matched_status_t& s);
  void on_liveliness(dds_entity_t reader, const dds_liveliness_changed_status_t& s);
  void on_deadline(const dds_requested_deadline_missed_status_t& s) {
    shared_.sink(detail::DeadlineMissedEvent{kind_, instance_handle(s.last_instance_handle)});
  }
  void on_incompatible(const dds_requested_incompatible_qos_status_t& s) {
    // Cyclone counts a writer in another partition (another device's) as
    // incompatible; the DDS specification and Fast DDS do not, and it is no
    // fault: the tap subscribes to the partitions it wants.
    if (s.last_policy_id == DDS_PARTITION_QOS_POLICY_ID) return;
    shared_.sink(detail::IncompatibleQosEvent{kind_, std::to_string(s.last_policy_id)});
  }

 protected:
  // The GUID of a matched writer (cached); a writer Cyclone no longer knows
  // and never cached keeps its local handle, marked by a zero prefix.
  Handle writer_guid(dds_entity_t reader, dds_instance_handle_t publication);
  void gone(dds_entity_t reader, const dds_sample_info_t& info) {
    const auto writer =
        info.publication_handle == 0 ? Handle{} : writer_guid(reader, info.publication_handle);
    shared_.sink(detail::InstanceGoneEvent{kind_, instance_handle(info.instance_handle),
                                           info.instance_state == DDS_IST_NOT_ALIVE_DISPOSED,
                                           writer});
  }

  TopicKind kind_;
  std::size_t interaction_;
  TapShared& shared_;

 private:
  std::mutex guids_mutex_;
  std::unordered_map<dds_instance_handle_t, Handle> guids_;
};

Handle ReaderTap::writer_guid(dds_entity_t reader, dds_instance_handle_t publication) {
  const std::lock_guard<std::mutex> lock(guids_mutex_);
  if (const auto it = guids_.find(publication); it != guids_.end()) return it->second;
  if (dds_builtintopic_endpoint_t* ep = dds_get_matched_publication_data(reader, publication)) {
    Handle guid{};
    std::copy_n(ep->key.v, guid.size(), guid.begin());
    dds_builtintopic_free_endpoint(ep);
    guids_[publication] = guid;
    return guid;
  }
  return instance_handle(publication);
}

void ReaderTap::on_matched(dds_entity_t reader, const dds_subscription_matched_status_t& s) {
  if (s.current_count_change > 0) {
    writer_guid(reader, s.last_publication_handle);  // cached while it can be asked
  } else if (s.current_count_change < 0) {
    const auto guid = writer_guid(reader, s.last_publication_handle);
    shared_.sink(detail::WriterLivelinessEvent{kind_, guid, false, true});
    const std::lock_guard<std::mutex> lock(guids_mutex_);
    guids_.erase(s.last_publication_handle);
  }
}

void ReaderTap::on_liveliness(dds_entity_t reader, const dds_liveliness_changed_status_t& s) {
  if (s.alive_count_change != 0) {
    shared_.sink(detail::WriterLivelinessEvent{
        kind_, writer_guid(reader, s.last_publication_handle), s.alive_count_change > 0});
  }
}

template <typename Sample>
class TypedReaderTap final : public ReaderTap {
 public:
  using ReaderTap::ReaderTap;

  void take_all(dds_entity_t reader) override {
    constexpr std::size_t kBatch = 16;
    std::array<void*, kBatch> samples{};
    std::array<dds_sample_info_t, kBatch> infos{};
    for (;;) {
      samples.fill(nullptr);  // loaned from Cyclone
      const dds_return_t n = dds_take(reader, samples.data(), infos.data(), kBatch, kBatch);
      if (n <= 0) return;  // no data, or the reader is being deleted
      for (dds_return_t i = 0; i < n; ++i) {
        const auto& info = infos[static_cast<std::size_t>(i)];
        if (info.valid_data) {
          emit(reader, *static_cast<const Sample*>(samples[static_cast<std::size_t>(i)]), info);
        } else if (info.instance_state != DDS_IST_ALIVE) {
          gone(reader, info);
        }
      }
      dds_return_loan(reader, samples.data(), n);
    }
  }

 private:
  void emit(dds_entity_t reader, const Sample& s, const dds_sample_info_t& info) {
    const auto writer = writer_guid(reader, info.publication_handle);
    const auto instance = instance_handle(info.instance_handle);
    if constexpr (std::is_same_v<Sample, mtc_idl_DeviceDescription>) {
      shared_.sink(detail::DeviceEvent{writer, instance, cyclone::from_c(s)});
    } else if constexpr (std::is_same_v<Sample, mtc_idl_Heartbeat>) {
      shared_.counters.heartbeats.fetch_add(1, std::memory_order_relaxed);
      shared_.sink(detail::HeartbeatEvent{writer, instance, cyclone::from_c(s)});
    } else if constexpr (std::is_same_v<Sample, mtc_idl_InteractionSample>) {
      detail::ParticipantKey paired{};
      auto value = cyclone::from_c(s, &paired);
      if (!detail::on_its_interaction_topic(value, interaction_)) {
        shared_.sink(detail::ProtocolViolationEvent{interaction_, writer, std::move(value)});
        return;
      }
      shared_.counters.values.fetch_add(1, std::memory_order_relaxed);
      shared_.sink(detail::ValueEvent{kind_, writer, instance, std::move(value), paired});
    } else {
      shared_.counters.values.fetch_add(1, std::memory_order_relaxed);
      shared_.sink(detail::ValueEvent{kind_, writer, instance, cyclone::from_c(s), {}});
    }
  }
};

// Cyclone's C callbacks, each forwarding to the ReaderTap in `arg`.
void data_available(dds_entity_t reader, void* arg) {
  static_cast<ReaderTap*>(arg)->take_all(reader);
}
void subscription_matched(dds_entity_t reader, const dds_subscription_matched_status_t s,
                          void* arg) {
  static_cast<ReaderTap*>(arg)->on_matched(reader, s);
}
void liveliness_changed(dds_entity_t reader, const dds_liveliness_changed_status_t s, void* arg) {
  static_cast<ReaderTap*>(arg)->on_liveliness(reader, s);
}
void deadline_missed(dds_entity_t, const dds_requested_deadline_missed_status_t s, void* arg) {
  static_cast<ReaderTap*>(arg)->on_deadline(s);
}
void incompatible_qos(dds_entity_t, const dds_requested_incompatible_qos_status_t s, void* arg) {
  static_cast<ReaderTap*>(arg)->on_incompatible(s);
}

cyclone::Listener make_listener(ReaderTap& tap) {
  cyclone::Listener l(dds_create_listener(&tap));
  if (!l) throw CreationError("dds_create_listener");
  dds_lset_data_available(l.get(), data_available);
  dds_lset_subscription_matched(l.get(), subscription_matched);
  dds_lset_liveliness_changed(l.get(), liveliness_changed);
  dds_lset_requested_deadline_missed(l.get(), deadline_missed);
  dds_lset_requested_incompatible_qos(l.get(), incompatible_qos);
  return l;
}

qos::EndpointQos reader_preset(TopicKind kind, const TapConfig& config) {
  switch (kind) {
    case TopicKind::DeviceDescription:
      return qos::device_description_topic(config.timing);
    case TopicKind::Heartbeat:
      return config.observer ? qos::heartbeat_observer_topic(config.timing)
                             : qos::heartbeat_topic(config.timing);
    default:
      return config.observer ? qos::state_observer_topic(config.timing)
                             : qos::state_topic(config.timing);
  }
}

std::unique_ptr<ReaderTap> make_reader_tap(TopicKind kind, std::size_t interaction,
                                           TapShared& shared) {
  switch (kind) {
    case TopicKind::Request:
    case TopicKind::Response:
      return std::make_unique<TypedReaderTap<mtc_idl_InteractionSample>>(kind, interaction, shared);
    case TopicKind::InterfaceState:
      return std::make_unique<TypedReaderTap<mtc_idl_InterfaceStateSample>>(kind, interaction,
                                                                            shared);
    case TopicKind::DoorState:
      return std::make_unique<TypedReaderTap<mtc_idl_DoorStateSample>>(kind, interaction, shared);
    case TopicKind::ChuckState:
      return std::make_unique<TypedReaderTap<mtc_idl_ChuckStateSample>>(kind, interaction, shared);
    case TopicKind::DeviceDescription:
      return std::make_unique<TypedReaderTap<mtc_idl_DeviceDescription>>(kind, interaction, shared);
    case TopicKind::Heartbeat:
      return std::make_unique<TypedReaderTap<mtc_idl_Heartbeat>>(kind, interaction, shared);
  }
  return nullptr;
}

class CycloneTap final : public Tap {
 public:
  CycloneTap(dds_entity_t participant, CycloneTopics& topics, const TapConfig& config, TapSink sink)
      : subscriber_(dds_create_subscriber(
                        participant, qos::cyclone_partition_qos(config.partitions).get(), nullptr),
                    "dds_create_subscriber") {
    shared_.sink = std::move(sink);
    for (std::size_t i = 0; i < detail::kTopicKindCount; ++i) {
      const auto kind = static_cast<TopicKind>(i);
      if (!config.topics[i] || kind == TopicKind::Request || kind == TopicKind::Response) continue;
      add_reader(kind, detail::kInteractionTopicCount, topics.topic(kind), config);
    }
    for (std::size_t i = 0; i < detail::kInteractionTopicCount; ++i) {
      const auto side = detail::interaction_side(i);
      if (!config.topics[static_cast<std::size_t>(side)] || !config.interactions[i]) continue;
      add_reader(side, i, topics.interaction_topic(i), config);
    }
  }
  ~CycloneTap() override {
    // Readers first: once dds_delete returns, no callback of theirs runs,
    // so the listeners' targets may go.
    for (auto& r : readers_) r.reset();
    subscriber_.reset();
  }
  CycloneTap(const CycloneTap&) = delete;
  CycloneTap& operator=(const CycloneTap&) = delete;
  CycloneTap(CycloneTap&&) = delete;
  CycloneTap& operator=(CycloneTap&&) = delete;

  TapCounts counts() const noexcept override {
    return {shared_.counters.values.load(std::memory_order_relaxed),
            shared_.counters.heartbeats.load(std::memory_order_relaxed)};
  }
  std::size_t reannounce() override { return 0; }  // as CyclonePublisher::reannounce

 private:
  void add_reader(TopicKind kind, std::size_t interaction, dds_entity_t topic,
                  const TapConfig& config) {
    taps_.push_back(make_reader_tap(kind, interaction, shared_));
    const auto listener = make_listener(*taps_.back());
    readers_.emplace_back(
        dds_create_reader(subscriber_.get(), topic,
                          qos::cyclone_reader_qos(reader_preset(kind, config)).get(),
                          listener.get()),
        "dds_create_reader");
  }

  TapShared shared_;
  std::vector<std::unique_ptr<ReaderTap>> taps_;  // outlive the readers that call them
  Entity subscriber_;
  std::vector<Entity> readers_;
};

}  // namespace

std::unique_ptr<Tap> make_cyclone_tap(int participant, CycloneTopics& topics,
                                      const TapConfig& config, TapSink sink) {
  return std::make_unique<CycloneTap>(participant, topics, config, std::move(sink));
}

}  // namespace mtc::dds::mw
