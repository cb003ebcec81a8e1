// The parts of an Equipment's internal state (EquipmentImpl): its service
// slots, interfaces and timing groups with their writers and readers. Like
// EquipmentImpl, touched only by the owner of the state, except the
// snapshot atomics.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "door_chuck.hpp"
#include "mtc/dds/detail/topic_names.hpp"
#include "mtc/dds/equipment.hpp"
#include "mw/middleware.hpp"
#include "peer_groups.hpp"

namespace mtc::dds {

using SteadyClock = std::chrono::steady_clock;

struct PendingRequest {
  std::shared_ptr<std::promise<RequestResult>> promise;
  std::function<void(const RequestResult&)> callback;
  SteadyClock::time_point started{};
  SteadyClock::time_point ready_deadline{};  // waiting for the counterpart READY
  bool issued = false;                       // the request went ACTIVE
};

// One published data item.
struct PublishedItem {
  std::string id;
  std::int64_t changed_ns = 0;  // source_time_ns of the current value
  std::uint64_t seq = 0;        // change number of its newest write
};

struct ServiceSlot {
  std::size_t interface_index = 0;
  core::Service service = core::Service::MaterialLoad;
  core::Role role = core::Role::Requester;
  std::size_t topic = 0;  // detail::interaction_index of the topic it writes
  ServiceOptions options;
  ResponderCallbacks responder_callbacks;
  std::unique_ptr<ServiceHandle> handle;
  PublishedItem item;
  std::optional<PendingRequest> pending;
  // The FAIL we are in was entered while idle (nothing to reset).
  bool idle_failure = false;
  core::Reason fail_reason = core::Reason::None;
  // Counterpart item: last sequence number seen from its writer.
  std::uint64_t counterpart_seq = 0;
  // Requester: the counterpart's newest response names this interface as
  // its pairing; only then does a request go ACTIVE.
  bool addressed = false;
  std::atomic<core::InteractionState> snap_state{core::InteractionState::Unavailable};
  std::atomic<core::InteractionState> snap_counterpart{core::InteractionState::Unavailable};
};

// An interface's DOOR_STATE or CHUCK_STATE item, published when the
// equipment controls that door or chuck.
template <typename State>
struct DoorChuckItem {
  bool published = false;
  PublishedItem item;
  State state = State::Unavailable;
};

// A timing group's writer of DOOR_STATE or CHUCK_STATE items (created only
// when one of its interfaces publishes them) and its change counter.
template <typename State>
struct DoorChuckWriter {
  std::unique_ptr<mw::ValueWriter> writer;
  std::uint64_t seq = 0;
  std::uint64_t history_scan_at = 0;  // see bound_history
};

// The writer of one interaction topic (service and side) and its change
// counter: the sequence_number of its samples, announced by the heartbeat.
struct InteractionWriter {
  std::unique_ptr<mw::ValueWriter> writer;
  std::uint64_t seq = 0;
  std::uint64_t history_scan_at = 0;  // see bound_history
};

// Writers, readers and heartbeat of the interfaces sharing one timing
// (DEADLINE and liveliness are heartbeat writer/reader QoS, so interfaces
// with their own heartbeat get their own endpoints). Group 0 is the
// equipment's; its index is the `group` of its Heartbeat instance and the
// `heartbeat_group` of its state samples.
struct TimingGroup {
  qos::Timing timing;
  // Indexed by detail::interaction_index; only those its interfaces use.
  std::array<InteractionWriter, detail::kInteractionTopicCount> interaction;
  std::unique_ptr<mw::ValueWriter> interface_writer;
  std::tuple<DoorChuckWriter<core::DoorState>, DoorChuckWriter<core::ChuckState>> door_chuck;
  std::unique_ptr<mw::HeartbeatWriter> heartbeat_writer;
  std::uint64_t interface_seq = 0;
  std::uint64_t interface_history_scan_at = 0;  // see bound_history
  // Change numbers already written, per state topic and per interaction
  // topic: what the heartbeat announces (written on the executor, read by
  // the heartbeat thread).
  std::array<std::atomic<std::uint64_t>, detail::kStateTopicCount> written{};
  std::array<std::atomic<std::uint64_t>, detail::kInteractionTopicCount> interaction_written{};
  std::uint64_t beats = 0;          // heartbeat thread only
  ObservedHeartbeat out_heartbeat;  // heartbeat thread only: reused, so a beat allocates little
  std::unique_ptr<mw::Tap> tap;
  std::array<bool, detail::kTopicKindCount> incompatible_reported{};

  template <typename State>
  DoorChuckWriter<State>& door_chuck_writer() {
    return std::get<DoorChuckWriter<State>>(door_chuck);
  }
};

// on_value asks every interface for every value received, next_wake after
// every step: what they read of each shares its first cache line.
struct alignas(64) InterfaceSlot {
  std::size_t group = 0;  // index into EquipmentImpl::groups
  std::atomic<LinkState> link{LinkState::Unpaired};
  // When the election among candidates is due (pairing by rule, below).
  std::optional<SteadyClock::time_point> elect_at;

 private:
  std::size_t cp_hash_ = counterpart_hash({}, {});
  mutable SteadyClock::time_point deadline_{};
  mutable bool deadline_known_ = false;
  bool change_noted_ = false;  // already in *changed_ since next_wake took it
  std::size_t index_ = 0;      // in EquipmentImpl::interfaces
  std::vector<std::size_t>* changed_ = nullptr;

 public:
  InterfaceConfig config;
  core::DoorChuckPreconditions hook;
  std::vector<std::size_t> services;  // indices into EquipmentImpl::slots
  PublishedItem state_item;
  std::tuple<DoorChuckItem<core::DoorState>, DoorChuckItem<core::ChuckState>> door_chuck;
  // Counterpart binding and link; set with name_counterpart.
  std::string cp_uuid;
  std::string cp_interface;
  // Which of the counterpart device's heartbeats vouches for its interface
  // (known from its first value), and which incarnation wrote that value.
  std::optional<detail::PeerGroupKey> cp_group;
  // Last value of each counterpart item (by data item id), and the items the
  // machines have not been given again since the link was lost.
  std::map<std::string, ObservedValue> cp_values;
  std::set<std::string> cp_stale;
  // When the newest value or heartbeat of the counterpart came (steady_ns).
  std::int64_t last_heard_steady_ns = 0;
  // Pairing by rule (no counterpart device configured): every complementary
  // interface announced (device uuid, interface id); elect_at (above) is set
  // by the first candidate while unpaired.
  std::set<std::pair<std::string, std::string>> candidates;
  bool paired_by_rule() const { return config.counterpart.device_uuid.empty(); }

  template <typename State>
  DoorChuckItem<State>& door_chuck_item() {
    return std::get<DoorChuckItem<State>>(door_chuck);
  }

  // Sets or (with empty ids) clears the counterpart's ids; the caller holds
  // EquipmentImpl::binding_mutex.
  void name_counterpart(const std::string& device, const std::string& interface_id) {
    cp_uuid = device;
    cp_interface = interface_id;
    cp_hash_ = counterpart_hash(device, interface_id);
  }
  // Whether a value of (device, interface_id), whose counterpart_hash is
  // `hash`, comes from our counterpart interface. on_value asks every
  // interface for every value: the hash spares 100 string compares.
  bool is_counterpart(std::string_view device, std::string_view interface_id,
                      std::size_t hash) const {
    return cp_hash_ == hash && cp_uuid == device && cp_interface == interface_id;
  }
  static std::size_t counterpart_hash(std::string_view device, std::string_view interface_id) {
    const std::size_t d = std::hash<std::string_view>{}(device);
    return d ^ (std::hash<std::string_view>{}(interface_id) + 0x9e3779b97f4a7c15ULL + (d << 6) +
                (d >> 2));
  }

  void set_model(std::unique_ptr<core::InterfaceModel> m) {
    model_ = std::move(m);
    deadline_known_ = false;
    note_change();
  }
  // From now on every change to the machines appends `index` to `changed`
  // once, until the owner of `changed` takes it (EquipmentImpl::next_wake,
  // which then keeps one deadline per interface instead of asking all).
  void track_changes(std::vector<std::size_t>* changed, std::size_t index) {
    changed_ = changed;
    index_ = index;
    change_noted_ = false;
    note_change();
  }
  void change_taken() { change_noted_ = false; }
  // Its place in EquipmentImpl::interfaces (set by track_changes, at start).
  std::size_t index() const { return index_; }
  const core::InterfaceModel& model() const { return *model_; }
  // Every change to the machines goes through here, and forgets the cached
  // deadline: next_wake asks every interface after every step, and with 100
  // interfaces recomputing each one's was a tenth of the runtime's CPU.
  core::InterfaceModel& model_to_change() {
    deadline_known_ = false;
    note_change();
    return *model_;
  }
  // The machines' next time limit (core::InterfaceModel::next_deadline, a
  // function of their state alone), computed again only after a change.
  SteadyClock::time_point next_deadline() const {
    if (!deadline_known_) {
      deadline_ = model_->next_deadline();
      deadline_known_ = true;
    }
    return deadline_;
  }

 private:
  void note_change() {
    if (changed_ == nullptr || change_noted_) return;
    change_noted_ = true;
    changed_->push_back(index_);
  }

  std::unique_ptr<core::InterfaceModel> model_;
};

}  // namespace mtc::dds
