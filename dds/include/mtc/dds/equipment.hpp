// The runtime a piece of equipment links: one Equipment object per device.
//
//   mtc::dds::EquipmentOptions o;
//   o.domain_id = 0; o.device_uuid = "cnc-1"; o.device_name = "CNC";
//   mtc::dds::Equipment cnc(o);
//   cnc.add_interface({"mh1", core::InterfaceType::MaterialHandler, "", {"robot-1", ""}});
//   auto& load = cnc.add_requester("mh1", core::Service::MaterialLoad);
//   cnc.start();
//   RequestResult r = load.request().get();   // COMPLETE, FAIL, timed out, comms lost
//
// The library publishes this device's data items (one DDS instance each, in
// partition "mtc/dev/<uuid>", written when they change), a heartbeat per
// timing group (mtc/Heartbeat, every period, from a thread of its own) and a
// DeviceDescription, subscribes to the counterpart's items and heartbeats,
// and runs the core state machines (Tables 5/6, scenarios 1-6) against what
// it sees.
//
// Threading: every application callback runs on this object's single
// executor thread, in order, and a command's future becomes ready there, after
// the callbacks of its step. The core machines are stepped one step at a
// time, in order: a received value or a command that finds the equipment
// idle at once on the thread that brought it (a DDS receive thread, the
// caller's), anything else and the timers (time limits, heartbeat checks) on
// the executor thread; a callback therefore may see snapshots (state(),
// counterpart_state()) newer than its event. EquipmentOptions::
// steps_on_executor hands every step to the executor thread as well;
// inline_steps runs the callbacks too on the thread that stepped. Commands
// (request(), complete(), ...) may be called from any thread, including
// from callbacks; they return futures that become ready once applied.
// Never block on such a future inside a callback (the executor would wait for
// itself), never destroy the Equipment from its own callback, and keep
// callbacks short: the heartbeat thread withholds the heartbeat while the
// executor makes no progress for a lease, so a callback that blocks for a
// lease looks like a hung device to the peers (which is what it is), and
// is written to stderr at once ("heartbeat group N withheld").
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mtc/core/interface_model.hpp"
#include "mtc/core/profile.hpp"
#include "mtc/core/result.hpp"
#include "mtc/core/vocabulary.hpp"
#include "mtc/dds/domain_observer.hpp"
#include "mtc/dds/error.hpp"
#include "mtc/dds/middleware.hpp"
#include "mtc/qos/participant.hpp"
#include "mtc/qos/timing.hpp"

namespace mtc::dds {

// Who clears a FAIL (Part 5: "resets any partial actions ... then READY").
enum class RecoveryPolicy : std::uint8_t {
  // The application calls recover() after every FAIL.
  Manual,
  // Default. FAILs with nothing to reset clear to READY by themselves once
  // the counterpart acknowledged them and communication is up: a FAIL caused
  // by loss of communication (scenario 6), or a counterpart FAIL seen while
  // this side was idle. Failures during a service wait for recover().
  AfterCommsLoss,
  // Every FAIL clears to READY once acknowledged and communication is up.
  Always,
};

// How a request ended.
enum class Outcome : std::uint8_t {
  Completed,  // the responder reported COMPLETE; the request is READY again
  Failed,     // responder FAIL, unexpected state change, protocol violation, fail()
  TimedOut,   // a configured time limit expired (core::TimeLimits)
  CommsLost,  // the counterpart was lost while the request was ACTIVE
  Rejected,   // the request was not issued (reason says why: NotReady, CounterpartBusy...)
  // The responder interface is paired with another requester (LinkState::
  // Excluded; the LinkEvent's cause names the pairing): not served, and not
  // a failure of either side. Withdrawn at once if it was already ACTIVE.
  Excluded,
};
std::string_view to_string(Outcome o) noexcept;

struct RequestResult {
  Outcome outcome = Outcome::Rejected;
  core::Reason reason = core::Reason::None;
  std::chrono::nanoseconds elapsed{0};  // request() to outcome, steady clock
};

struct RequestOptions {
  // When the counterpart is not READY yet (not discovered, busy, recovering),
  // wait up to this long for it instead of rejecting at once.
  std::chrono::milliseconds wait_for_ready{0};
};

// Which device/interface one of our interfaces pairs with. Both fields
// given: exactly that interface. Only the device uuid: the first interface of
// that device, announced or heard from, of the same type (with that id, if
// given) carrying the opposite side of one of our services. Neither: the
// pairing rule (docs/interaction-model.md, Pairing): every such interface
// announced within EquipmentOptions::pairing_settle of the first one is a
// candidate, the lowest (device uuid, interface id) wins, and the pairing
// holds until that device leaves (disposes its instances on a graceful end;
// a lost one is waited for, scenario 6).
struct CounterpartSpec {
  std::string device_uuid;
  std::string interface_id;
};

// The most interfaces one Equipment declares: its announcement
// (DeviceDescription in idl/mtconnect_interfaces.idl) carries them all, in a
// sequence bounded at this, and a reader of another DDS vendor drops a sample
// beyond a bound. add_interface refuses one more.
inline constexpr std::size_t kMaxInterfacesPerDevice = 128;

struct InterfaceConfig {
  std::string id;  // unique within the device, e.g. "mh1"
  core::InterfaceType type = core::InterfaceType::MaterialHandler;
  std::string name;  // defaults to id
  CounterpartSpec counterpart;
  // This equipment controls the door / chuck: it publishes DOOR_STATE /
  // CHUCK_STATE for this interface and its responders obey them (OPEN_DOOR is
  // NOT_READY while the door is OPEN, core::DoorChuckPreconditions).
  bool publishes_door_state = false;
  bool publishes_chuck_state = false;
  core::DoorState initial_door_state = core::DoorState::Unavailable;
  core::ChuckState initial_chuck_state = core::ChuckState::Unavailable;
  // Heartbeat and lease of this interface (its timing group's heartbeat
  // writer and readers: DEADLINE and liveliness); default: the equipment's.
  // The counterpart's interface must use the same (or a faster) timing.
  std::optional<qos::Timing> timing{};
};

// Time limits an Equipment uses unless told otherwise: as core's defaults,
// plus fail_ack = 2 s so that a FAIL whose acknowledgement was lost (the
// counterpart's FAIL replaced by READY while we were cut off) cannot pin a
// side in FAIL forever: after 2 s recovery no longer waits for it.
inline core::TimeLimits default_time_limits() {
  core::TimeLimits l{};
  l.fail_ack = std::chrono::seconds(2);
  return l;
}

struct ServiceOptions {
  core::TimeLimits limits = default_time_limits();
  bool start_ready = true;
  bool counterpart_has_fail = true;
  // Responder: accept an observed request at once (when permitted) and then
  // call on_request; false: on_request is called on observation and the
  // application calls accept() itself.
  bool auto_accept = true;
};

// One step of one of this equipment's service machines, with timestamps for
// latency measurement (all *_ns are CLOCK_REALTIME ns since the epoch; 0 = n/a).
struct TransitionEvent {
  std::string interface_id;
  core::StepResult step;  // service, role, event, previous, current, notice, reason
  core::InteractionState counterpart = core::InteractionState::Unavailable;
  std::int64_t trigger_source_time_ns = 0;   // counterpart's change time (Seen* events)
  std::int64_t trigger_receive_time_ns = 0;  // when our listener received that sample
  std::int64_t step_time_ns = 0;             // when the executor ran the step
  std::int64_t publish_time_ns = 0;          // when our new state was written (if changed)
};

enum class LinkState : std::uint8_t {
  Unpaired,  // no counterpart chosen yet
  Paired,    // counterpart known, none of its values seen yet
  Up,        // counterpart values arriving
  Lost,      // liveliness/deadline lost, disposed, or its INTERFACE_STATE UNAVAILABLE
  // The counterpart interface is paired with another device/interface (its
  // interaction samples name it; cause: "machine-1/mh is paired with
  // robot-1/mh"): its values are not ours, nothing is requested or served.
  // Up again when it names this interface (or nobody).
  Excluded,
};
std::string_view to_string(LinkState s) noexcept;

struct LinkEvent {
  std::string interface_id;
  std::string counterpart_uuid;
  std::string counterpart_interface_id;
  LinkState previous = LinkState::Unpaired;
  LinkState current = LinkState::Unpaired;
  std::string cause;         // "liveliness lost", "deadline missed", "disposed", ...
  std::int64_t time_ns = 0;  // CLOCK_REALTIME when the executor handled it
  // For Lost: time since the last sample from the counterpart (detection
  // time), on the steady clock: a step of the wall clock does not change it.
  std::chrono::nanoseconds silence{0};
};

struct EquipmentCallbacks {
  std::function<void(const TransitionEvent&)> on_transition;
  std::function<void(const LinkEvent&)> on_link;
  // Every value of a paired counterpart (interaction items, INTERFACE_STATE,
  // DOOR_STATE, CHUCK_STATE): each change as it arrives, and after a loss of
  // communication the last known values again once the counterpart's
  // heartbeats are back (redelivered = true). A device also writes an item
  // that has not changed for a long while again (same value and source
  // time, new sequence number; see docs/heartbeat.md). Heartbeats themselves
  // are not values. Called before the transitions the value causes; the
  // handle's counterpart_state() already shows the value by then.
  std::function<void(const ObservedValue&)> on_counterpart_value;
  // Diagnostics: incompatible QoS offered by a peer, callback exceptions,
  // heartbeats withheld by the watchdog, announced changes not received.
  std::function<void(const std::string&)> on_diagnostic;
};

// Samples an Equipment has written and taken since start() (benchmarks,
// diagnostics). Received counts are per reader: with several timing groups a
// sample that reaches the readers of two groups counts twice.
struct Traffic {
  std::uint64_t values_written = 0;  // state samples: changes only
  std::uint64_t heartbeats_written = 0;
  std::uint64_t values_received = 0;
  std::uint64_t heartbeats_received = 0;
  // Passes that announced every endpoint of the participant again (after a
  // lost counterpart, and in the background; docs/multihost.md, "Cable
  // pull"), and how many endpoints the latest one announced.
  std::uint64_t reannounce_passes = 0;
  std::uint64_t endpoints_reannounced = 0;
};

struct EquipmentOptions {
  int domain_id = 0;
  std::string device_uuid;
  std::string device_name;  // defaults to device_uuid
  qos::Timing timing;       // heartbeat, lease, RTPS heartbeat, discovery
  // Network (Fast DDS's UDPv4 + SHM, default discovery) reaches the cell's
  // other hosts; qos::Transport::Loopback keeps DDS on this host.
  qos::Transport transport = qos::Transport::Network;
  qos::FaultInjection faults;  // qos::Transport::LoopbackTest only
  // The DDS implementation (mtc/dds/middleware.hpp); equipment on different
  // ones share a cell. Cyclone: not the test transport; secured, see
  // docs/security.md for a mixed cell.
  Middleware middleware = Middleware::FastDds;
  core::Profile profile = core::Profile::V1_6;
  RecoveryPolicy recovery = RecoveryPolicy::AfterCommsLoss;
  // DDS-Security identity of this device (scripts/security/make-pki.sh);
  // empty: unsecured. A bad directory is a ConfigError naming the file.
  std::string security_dir;
  // Interfaces paired by rule (no counterpart device configured) wait this
  // long after the first candidate's announcement before choosing, so that
  // counterparts started together are all candidates (0..60 s).
  std::chrono::milliseconds pairing_settle{500};
  // Where the state machines are stepped (docs/benchmarks.md, "Stepping").
  // By default a received value or a command that finds the equipment idle
  // is stepped at once on the thread that brought it (a middleware receive
  // thread, or the application thread calling a command), while every
  // callback and every command's result still goes to the executor thread,
  // in order: no thread hand-off in a transit that needs no application
  // decision (the requester's READY after COMPLETE, say).
  // steps_on_executor: every DDS event and command is handed to the executor
  // thread first, one hand-off more per transit (the default before 2026-12).
  bool steps_on_executor = false;
  // inline_steps: the callbacks too run at once on the thread that brought
  // the step, one at a time and in order: the fastest path, but vendor code
  // then runs on the middleware's threads and must never block there.
  // Takes precedence over steps_on_executor.
  bool inline_steps = false;
  // pack_callback_writes (needs inline_steps): what a step wrote waits for
  // its callbacks and leaves with what they wrote (a command's future is
  // still made ready after the writes left). Over Cyclone DDS a responder's
  // ACTIVE then shares one message with the COMPLETE its on_request wrote:
  // less CPU per handshake under load, but a counterpart that was idle
  // starts waking only once the callbacks are done, so a single handshake
  // takes longer (docs/benchmarks.md, "Writes packed with their callbacks'").
  // Fast DDS sends every write at once: no effect there.
  bool pack_callback_writes = false;
};

class Equipment;
struct EquipmentImpl;

// One side (requester or responder) of one service on one interface. Owned
// by its Equipment; valid as long as the Equipment.
class ServiceHandle {
 public:
  const std::string& interface_id() const noexcept;
  core::Service service() const noexcept;
  core::Role role() const noexcept;
  // Latest published state / counterpart state (thread-safe snapshots).
  core::InteractionState state() const noexcept;
  core::InteractionState counterpart_state() const noexcept;

  // Commands (any thread). The future holds the machine's StepResult; a
  // refused command has notice Rejected and a reason, nothing changes.
  std::future<core::StepResult> fail();
  std::future<core::StepResult> recover(
      core::InteractionState target = core::InteractionState::Ready);
  std::future<core::StepResult> set_ready(bool ready);
  // The same commands with a callback for the StepResult instead of a future
  // (on the executor thread, as request()'s; nullptr: no result wanted). For
  // the hot path of a handshake: settling a future costs a system call even
  // when nobody reads it (std::promise runs pthread_once, which always wakes).
  using OnStep = std::function<void(const core::StepResult&)>;
  void fail(OnStep on_result);
  void recover(core::InteractionState target, OnStep on_result);
  void set_ready(bool ready, OnStep on_result);

  ServiceHandle(const ServiceHandle&) = delete;
  ServiceHandle& operator=(const ServiceHandle&) = delete;
  virtual ~ServiceHandle() = default;

 protected:
  ServiceHandle(EquipmentImpl& impl, std::size_t slot) noexcept : impl_(impl), slot_(slot) {}
  std::future<core::StepResult> command(core::Event event);
  void command(core::Event event, OnStep on_result);
  EquipmentImpl& impl_;
  std::size_t slot_;
  friend struct EquipmentImpl;
};

class Requester final : public ServiceHandle {
 public:
  // READY -> ACTIVE, then waits for COMPLETE / FAIL / time limit / comms loss.
  // The request returns to READY by itself after COMPLETE (Table 1 step 5).
  std::future<RequestResult> request(RequestOptions options = {});
  // Same, with a callback on the executor thread instead of a future.
  void request(RequestOptions options, std::function<void(const RequestResult&)> on_result);

 private:
  using ServiceHandle::ServiceHandle;
  friend struct EquipmentImpl;
  friend class Equipment;
};

class Responder;

struct ResponderCallbacks {
  // A request arrived. With ServiceOptions::auto_accept (default) the
  // response is already ACTIVE: do the work, then complete() or fail().
  // Without it, call accept() (or leave it and let the requester time out).
  std::function<void(Responder&)> on_request;
  // The service in progress ended without complete(): the requester failed
  // or left ACTIVE (scenarios 3, 4), communication was lost (6), or a time
  // limit expired. Reset partial actions; see RecoveryPolicy.
  std::function<void(Responder&, core::Reason)> on_abort;
};

class Responder final : public ServiceHandle {
 public:
  std::future<core::StepResult> accept();
  std::future<core::StepResult> complete();
  // With a callback instead of a future (ServiceHandle::OnStep), e.g. in
  // on_request: `r.complete(nullptr)`.
  void accept(OnStep on_result);
  void complete(OnStep on_result);

 private:
  using ServiceHandle::ServiceHandle;
  friend struct EquipmentImpl;
  friend class Equipment;
};

class Equipment {
 public:
  // Validates the options (ConfigError); creates nothing on the network yet.
  explicit Equipment(EquipmentOptions options, EquipmentCallbacks callbacks = {});
  // Disposes this device's data items (peers see them UNAVAILABLE at once),
  // stops the executor and deletes every DDS entity.
  ~Equipment();
  Equipment(const Equipment&) = delete;
  Equipment& operator=(const Equipment&) = delete;

  // --- Declaration (before start(); ConfigError on bad input) -------------
  void add_interface(InterfaceConfig config);
  Requester& add_requester(const std::string& interface_id, core::Service service,
                           ServiceOptions options = {});
  Responder& add_responder(const std::string& interface_id, core::Service service,
                           ResponderCallbacks callbacks, ServiceOptions options = {});
  // Creates the participant, writers and readers, publishes the initial
  // states and the DeviceDescription, starts the executor. Throws Error.
  void start();

  // --- Runtime (any thread, after start()) --------------------------------
  std::future<void> set_interface_state(const std::string& interface_id,
                                        core::InterfaceState state);
  std::future<void> set_door_state(const std::string& interface_id, core::DoorState state);
  std::future<void> set_chuck_state(const std::string& interface_id, core::ChuckState state);
  // Runs `task` on the executor thread (after everything queued before it).
  void post(std::function<void()> task);

  // --- Lookup and snapshots (thread-safe) ---------------------------------
  Requester* requester(const std::string& interface_id, core::Service service) const noexcept;
  Responder* responder(const std::string& interface_id, core::Service service) const noexcept;
  LinkState link_state(const std::string& interface_id) const;
  // The paired counterpart of an interface, once known.
  std::optional<CounterpartSpec> counterpart(const std::string& interface_id) const;
  const EquipmentOptions& options() const noexcept;
  // The DDS implementation its participant runs on once started (before:
  // the one its options ask for).
  Middleware middleware() const noexcept;
  bool started() const noexcept;
  Traffic traffic() const;

 private:
  std::unique_ptr<EquipmentImpl> impl_;
};

}  // namespace mtc::dds
