// Internal state of an Equipment. Everything except the snapshot atomics and
// the configuration is touched only on the executor thread.
#pragma once

#include <array>
#include <atomic>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include "device_owners.hpp"
#include "door_chuck.hpp"
#include "earliest_of.hpp"
#include "equipment_slots.hpp"
#include "executor.hpp"
#include "heartbeat_thread.hpp"
#include "left_incarnations.hpp"
#include "lookup_keys.hpp"
#include "mtc/dds/detail/topic_names.hpp"
#include "mtc/dds/equipment.hpp"
#include "mw/middleware.hpp"
#include "mw/write_batch.hpp"
#include "peer_checks.hpp"
#include "peer_groups.hpp"
#include "reannounce.hpp"

namespace mtc::dds {

// The runtime's internals by their short names.
namespace topics = detail::topics;

struct EquipmentImpl {
  EquipmentOptions options;
  EquipmentCallbacks callbacks;
  std::vector<std::unique_ptr<InterfaceSlot>> interfaces;
  std::vector<std::unique_ptr<ServiceSlot>> slots;
  // next_wake's bookkeeping, kept by the owner of the state: the interfaces
  // whose machines changed since it last looked (InterfaceSlot::
  // track_changes), each interface's machine deadline as it last saw it, the
  // interfaces with an election scheduled and the service slots holding a
  // request not yet issued (both pruned as next_wake finds them done).
  std::vector<std::size_t> changed_interfaces;
  detail::EarliestOf interface_deadlines;
  std::vector<std::size_t> electing;
  std::vector<std::size_t> waiting_to_issue;
  std::atomic<bool> started{false};
  mutable std::mutex binding_mutex;  // guards cp_uuid / cp_interface for readers

  std::uint64_t description_seq = 0;

  // Which counterpart writer / instance belongs to which device and item.
  std::map<detail::Handle, std::string> writer_device;
  // The last value of every item of every device our readers saw, paired or
  // not: an interface that pairs later starts from what is already known
  // (items are written on change only; nothing else would bring them).
  struct SeenValue {
    detail::Handle writer{};
    ObservedValue value;
    detail::ParticipantKey paired{};
    std::int64_t heard_ns = 0;  // steady_ns
  };
  struct InstanceOwner {
    std::string device;
    std::string interface_id;
    std::string item;
    std::uint32_t group = 0;               // heartbeat instances
    detail::ParticipantKey participant{};  // the incarnation that last wrote it
    detail::Handle writer{};               // of a value instance: its last writer
    SeenValue* seen = nullptr;             // its entry in seen_values (never erased)
  };
  // Hashes the 16 bytes of an instance handle and its topic: looked up for
  // every value received, where a tree of every item of 100 interfaces
  // compared the 16 bytes a dozen times.
  struct InstanceKeyHash {
    std::size_t operator()(const std::pair<detail::TopicKind, detail::Handle>& key) const noexcept {
      std::uint64_t low = 0;
      std::uint64_t high = 0;
      std::memcpy(&low, key.second.data(), sizeof low);
      std::memcpy(&high, key.second.data() + sizeof low, sizeof high);
      return static_cast<std::size_t>((low ^ (high * 0x9e3779b97f4a7c15ULL)) * 31U +
                                      static_cast<std::uint64_t>(key.first));
    }
  };
  std::map<detail::Handle, std::set<std::string>> writer_interfaces;  // interfaces it feeds
  std::set<detail::Handle> description_writers;
  detail::DeviceOwners owners;  // who announced each counterpart device
  // Incarnations that said they are leaving: what they write later is not news.
  detail::LeftIncarnations left_incarnations;
  bool from_left_incarnation(const detail::Handle& writer) const {
    return left_incarnations.wrote(writer);
  }
  std::unordered_map<std::pair<detail::TopicKind, detail::Handle>, InstanceOwner, InstanceKeyHash>
      instance_item;
  // Last change number per (timing group whose tap saw it, writer).
  std::map<std::pair<std::size_t, detail::Handle>, std::uint64_t> writer_seq;
  detail::PeerGroups peer_groups;
  detail::PeerChecks peer_checks;  // what a peer writes that the types cannot forbid
  std::map<std::pair<std::string, std::string>, SeenValue, detail::ViewLess> seen_values;

  // Samples written (any thread), for Equipment::traffic().
  std::atomic<std::uint64_t> values_written{0};
  std::atomic<std::uint64_t> heartbeats_written{0};

  // DDS entities, declaration order = creation order (destroyed in reverse).
  detail::Executor executor;
  std::unique_ptr<mw::Participant> participant;
  detail::ParticipantKey self{};  // participant->key()
  // Per timing group: the beginning of the last own silence acted upon.
  std::vector<detail::HeartbeatThread::Clock::time_point> own_silence_handled;
  std::unique_ptr<mw::Publisher> publisher;
  std::unique_ptr<mw::DeviceWriter> description_writer;
  std::vector<std::unique_ptr<TimingGroup>> groups;
  std::unique_ptr<detail::HeartbeatThread> heartbeat_thread;  // after the writers it uses

  // --- lifecycle (equipment.cpp) ---
  InterfaceSlot& interface_slot(const std::string& id) const;
  std::size_t add_slot(const std::string& interface_id, core::Service service, core::Role role,
                       const ServiceOptions& opts);
  void create_entities();
  void group_by_timing();
  void create_group(std::size_t index);
  TimingGroup& group_of(const InterfaceSlot& itf) const { return *groups[itf.group]; }
  void shutdown() noexcept;
  template <typename R, typename Fn>
  std::future<R> run(Fn fn);
  // Runs fn() on the executor as run() does, for a caller that wants no
  // result (request() with a callback: the outcome goes to the callback).
  // A future costs a promise, a report to settle it and, under std::promise,
  // a futex wake (glibc's pthread_once) on every call. What fn throws is
  // reported as a diagnostic naming `what`.
  template <typename Fn>
  void run_unawaited(const char* what, Fn fn);
  // Equipment::set_door_state / set_chuck_state.
  template <typename State>
  std::future<void> set_door_chuck(const std::string& interface_id, State state);

  // --- publishing (equipment_publish.cpp) ---
  // The value being written (executor thread; reused, so its strings keep
  // their capacity and a write allocates nothing of ours).
  ObservedValue out_value;
  // Each writes a change (state topics carry nothing else).
  void publish_interaction(ServiceSlot& slot, std::int64_t now_ns);
  void publish_interface_state(InterfaceSlot& itf, std::int64_t now_ns);
  // DOOR_STATE or CHUCK_STATE of one interface, if it publishes that item;
  // defined for core::DoorState and core::ChuckState.
  template <typename State>
  void publish_door_chuck(InterfaceSlot& itf, std::int64_t now_ns);
  void publish_doors_and_chucks(InterfaceSlot& itf, std::int64_t now_ns);
  void publish_description();
  void wrote(TimingGroup& g, detail::TopicKind topic, std::uint64_t seq);
  void wrote_interaction(TimingGroup& g, std::size_t topic, std::uint64_t seq);
  // --- history span (equipment_history.cpp) ---
  // One writer's history: (group, topic), and for the interaction topics
  // (Request, Response) its interaction_index; `newest` is the writer's
  // change number, `scan_at` the first at which its items must be looked at.
  void bound_history(std::size_t group, detail::TopicKind topic, std::size_t interaction,
                     std::uint64_t newest, std::uint64_t& scan_at);
  template <typename Fn>
  void for_each_item(std::size_t group, detail::TopicKind topic, std::size_t interaction, Fn&& fn);
  bool bounding_history = false;
  // Heartbeat thread: one heartbeat of group `index`.
  // `leaving`: the last one, period 0 (see write_leaving_heartbeats).
  void write_heartbeat(std::size_t index, bool leaving = false);
  void write_leaving_heartbeats() noexcept;
  void start_heartbeats();
  detail::TapSink tap_sink(std::size_t group);
  void dispose_all() noexcept;
  // Bounded by `deadline`: see equipment_publish.cpp.
  bool await_acknowledgments(SteadyClock::time_point deadline) noexcept;

  // --- machines (equipment_machines.cpp) ---
  core::StepResult apply(ServiceSlot& slot, core::Event event, SteadyClock::time_point now,
                         std::int64_t source_ns = 0, std::int64_t receive_ns = 0);
  void handle_result(ServiceSlot& slot, const core::StepResult& r, std::int64_t source_ns,
                     std::int64_t receive_ns);
  void handle_batch(InterfaceSlot& itf, const core::StepBatch& batch);
  void auto_recover(ServiceSlot& slot, SteadyClock::time_point now);
  void resolve_pending(ServiceSlot& slot, const core::StepResult& r);
  void try_issue(ServiceSlot& slot, SteadyClock::time_point now);
  // Resolves the pending request (there must be one) with this result.
  void end_pending(ServiceSlot& slot, Outcome outcome, core::Reason reason);
  void on_wake(SteadyClock::time_point now);
  // Asked after every step: O(changes since the last call), not O(interfaces).
  SteadyClock::time_point next_wake();
  ServiceSlot* slot_for(InterfaceSlot& itf, core::Service service, core::Role role) const;

  // --- DDS events (equipment_events.cpp) ---
  void on_event(std::size_t group, detail::TapEvent& event);
  void on_value(std::size_t group, detail::ValueEvent& e);
  InstanceOwner& note_instance(const detail::ValueEvent& e, const ObservedValue& v);
  // heard_ns: when the value came (steady_ns).
  void note_counterpart_value(InterfaceSlot& itf, const detail::Handle& writer,
                              const ObservedValue& v, std::int64_t heard_ns);
  void deliver(InterfaceSlot& itf, const ObservedValue& v, bool missed_change);
  void on_heartbeat(std::size_t group, detail::HeartbeatEvent& e);
  void redeliver_stale(InterfaceSlot& itf);
  void feed_counterpart(ServiceSlot& slot, const ObservedValue& v, bool missed_change);
  void name_configured_counterparts();
  void bind_configured();
  void on_device(detail::DeviceEvent& e);
  // How a counterpart's instance ended: the last two are a graceful leave.
  enum class Gone { WithoutWriters, Disposed, Leaving };
  // `writer`: who ended the instance, when known (all zero: unknown).
  void on_gone(std::size_t group, detail::TopicKind topic, const detail::Handle& instance, Gone how,
               const detail::Handle& writer);
  void on_writer_lost(std::size_t group, const detail::Handle& writer, const char* cause,
                      bool check_silence);
  void on_deadline_missed(std::size_t group);
  SteadyClock::time_point next_silence_check() const;
  mutable std::optional<SteadyClock::time_point> silence_check_at;  // see next_silence_check
  void heard(InterfaceSlot& itf, std::int64_t heard_ns);
  void check_silence();
  void on_heartbeat_writer_lost(std::size_t group, const detail::PeerGroupKey& key,
                                const char* cause, bool check_silence);
  void owner_silent(std::size_t group, const detail::PeerGroupKey& key, bool check_silence);
  // Counterparts lost by silence (timing group, heartbeat group key): they
  // no longer own their device, whichever check found them, after the links
  // (a takeover pairs anew). The liveliness cue that would say so is ignored
  // when early and not repeated, and never comes for a heartbeat writer that
  // never matched: a restart of a hung device (its participant lives on)
  // would otherwise be refused for good.
  using SilentOwners = std::vector<std::pair<std::size_t, detail::PeerGroupKey>>;
  bool recently_heard(std::size_t group, std::int64_t last_ns, const std::string& what);
  bool heartbeat_cue_only(const InterfaceSlot& itf, const std::string& device);
  void link_lost(InterfaceSlot& itf, const std::string& cause);
  void link_up(InterfaceSlot& itf, const char* cause);
  void set_link(InterfaceSlot& itf, LinkState next, const std::string& cause);
  bool try_bind(InterfaceSlot& itf, const std::string& device, const std::string& interface_id);
  void replay_seen_values(InterfaceSlot& itf);
  // --- endpoint re-announcement (equipment_reannounce.cpp) ---
  detail::ReannounceSchedule reannounce;  // armed once every endpoint exists
  std::atomic<std::uint64_t> reannounce_passes{0};
  std::atomic<std::uint64_t> endpoints_reannounced{0};  // by the latest pass
  // Every endpoint of the participant announced again, if a pass is due.
  void reannounce_due(SteadyClock::time_point now);
  // --- pairing rule and exclusion (equipment_pairing.cpp) ---
  // A counterpart value for `itf`: link state, exclusion, delivery.
  void take_counterpart_value(InterfaceSlot& itf, const detail::Handle& writer,
                              const ObservedValue& v, std::int64_t heard_ns, bool missed_change);
  void add_candidate(InterfaceSlot& itf, const std::string& device,
                     const std::string& interface_id);
  void elect_due(SteadyClock::time_point now);
  void schedule_election(InterfaceSlot& itf);
  SteadyClock::time_point next_election();
  // The device disposed its instances (a graceful end): it is no longer a
  // candidate, and interfaces paired with it by rule are free again.
  void device_left(const std::string& device, const std::string& cause);
  void unpair(InterfaceSlot& itf, const std::string& cause);
  void exclude(InterfaceSlot& itf, const ObservedValue& v);
  void readmit(InterfaceSlot& itf);
  // Our pairing changed, or our counterpart is a new participant (restarted
  // under its uuid): every interaction item of the interface is written
  // again (same value and source time) naming it.
  void publish_pairing(InterfaceSlot& itf);
  // An interaction value naming our interface but another participant of
  // our uuid: written for a previous incarnation of this device.
  bool written_for_predecessor(const InterfaceSlot& itf, const ObservedValue& v,
                               const detail::ParticipantKey& paired) const noexcept;
  // Scenario 6 is symmetric: when our own heartbeats stopped long enough for
  // a counterpart to declare us lost (this process was stopped, starved or
  // hung), we take that counterpart as lost too, before acting on anything
  // it said before the gap (values that waited in our sockets meanwhile).
  void check_own_silence();
  void diagnostic(const std::string& text);
  // False (reported once) when `writer` is not of the participant that
  // announced `device`; an announcement claims an unowned device.
  bool owned_by_writer(const std::string& device, const detail::Handle& writer, detail::Said said);
  // Steps may run on other threads than the executor's (the default, see
  // EquipmentOptions::steps_on_executor): callbacks and command results then
  // go to the executor thread as reports, in order.
  bool defer_reports = false;
  // EquipmentOptions::pack_callback_writes: with inline_steps a callback
  // runs on the thread that stepped and must never block, so the step's
  // writes may wait for it and leave with what it wrote at the end of the
  // step (over Cyclone DDS one sendmsg here, and one wake-up and recvmsg at
  // each reader, for both). Otherwise what the step wrote is sent before
  // the callback runs: an idle counterpart starts waking meanwhile, and a
  // callback on the executor thread may take up to a lease.
  bool writes_wait_for_callbacks = false;
  // What settle() runs: a future made ready wakes the thread that waits on
  // it (a system call), which the step's writes never wait for; a callback
  // may (writes_wait_for_callbacks).
  enum class Settles { Future, Callback };
  // An application callback, at once or as a report: `fn` owns what it
  // needs, as it may run after the step.
  template <typename Fn>
  void report(const char* what, Fn fn) {
    settle([this, what, fn = std::move(fn)]() mutable { guard_callback(what, fn); },
           Settles::Callback);
  }
  // A command's future made ready (`settle` sets it), after its step's
  // callbacks; where every report goes.
  template <typename Fn>
  void settle(Fn settle, Settles what = Settles::Future) {
    if (defer_reports) {
      executor.post_report(std::move(settle));
      return;
    }
    // Run with the step (mw::WriteBatch): what the step wrote leaves first,
    // unless this is a callback and writes_wait_for_callbacks.
    if (what == Settles::Future || !writes_wait_for_callbacks) mw::WriteBatch::send_now();
    settle();
  }
  // Application callbacks must not take the executor down.
  template <typename Fn>
  void guard_callback(const char* what, Fn&& fn) {
    diagnose_throw(what, "callback threw", fn);
  }
  // Runs fn; what it throws becomes the diagnostic "<what> <verb>: <why>".
  template <typename Fn>
  void diagnose_throw(const char* what, const char* verb, Fn&& fn) {
    try {
      fn();
    } catch (const std::exception& e) {
      diagnostic(std::string(what) + ' ' + verb + ": " + e.what());
    } catch (...) {
      diagnostic(std::string(what) + ' ' + verb + ": an unknown exception");
    }
  }
};

}  // namespace mtc::dds
