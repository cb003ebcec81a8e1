// Passive view of a DDS domain: every device's announcements, every
// interface data item and every heartbeat, as plain values. Used by the
// bridge and by the `mtc watch` / `mtc list` commands; it never publishes
// anything. Devices write their items only when they change and tell that
// they are alive by heartbeats (one per timing group); the observer reports
// a group's items lost when its heartbeats stop, and hands their last known
// values over again when the heartbeats come back.
//
// Threading: DDS listeners only copy samples into a queue; every callback
// below runs on the observer's single dispatch thread, in arrival order.
// With DomainObserverOptions::inline_steps, a received sample that finds the
// observer idle is handled at once on the middleware's thread instead: still
// one callback at a time and in order, but possibly on that thread.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mtc/core/observation.hpp"
#include "mtc/dds/middleware.hpp"
#include "mtc/qos/participant.hpp"
#include "mtc/qos/timing.hpp"

namespace mtc::dds {

// The observed values are plain core types (mtc/core/observation.hpp), so
// that their consumers (the bridge's agent, printers) need no DDS; the
// aliases keep the names this header always offered.
using core::ItemKind;
using core::ObservedDataItem;
using core::ObservedDevice;
using core::ObservedHeartbeat;
using core::ObservedInterface;
using core::ObservedState;
using core::ObservedValue;

struct DomainObserverCallbacks {
  // A device's announcement; again (unchanged) when a lost device's
  // heartbeats come back.
  std::function<void(const ObservedDevice&)> on_device;
  // Each change of a data item; after a loss, the last known value again
  // (ObservedValue::redelivered) once its device's heartbeats are back and
  // every change they announce has arrived. An item unchanged for long may
  // also arrive again with the same value (its device keeps its writer's
  // history short).
  std::function<void(const ObservedValue&)> on_value;
  // The heartbeats that vouch for these data items stopped (or their device
  // disposed them, or left: its last heartbeat has period_ms 0): their
  // values must now read UNAVAILABLE.
  std::function<void(const std::string& device_uuid, const std::vector<std::string>& data_item_ids)>
      on_items_lost;
  // The device's own heartbeat (group 0) stopped, or it left: device gone.
  std::function<void(const std::string& device_uuid)> on_device_lost;
  // Every heartbeat (optional; 10 per second per device at the default),
  // the last one of a leaving device's group too (period_ms 0).
  std::function<void(const ObservedHeartbeat&)> on_heartbeat;
  // Without DDS-Security: a participant other than the device's live owner
  // (the one whose announcement was accepted) wrote an announcement, a value
  // or a heartbeat for it (reported once per device, participant and kind);
  // the sample was ignored, or held until the owner is lost (see
  // docs/security.md). Unset: the report goes to stderr.
  std::function<void(const std::string& device_uuid, const std::string& report)>
      on_ownership_conflict;
  // A device wrote what the Part 5 vocabulary or the wire contract forbids:
  // a state outside its item's vocabulary (the value still arrives: print it
  // as UNAVAILABLE), an interaction sample naming no known service or
  // sub-type (dropped), change numbers that go back or leap (reported once
  // per writer, item and rule), an interaction sample whose service or
  // sub-type disagrees with the topic it came on (mtc/InteractionResponse/
  // MATERIAL_LOAD carries MATERIAL_LOAD RESPONSE items only; dropped,
  // reported once per writer and topic). Unset: the report goes to stderr.
  std::function<void(const std::string& device_uuid, const std::string& report)>
      on_protocol_violation;
};

struct DomainObserverOptions {
  int domain_id = 0;
  // Endpoint QoS is not selectable: the observer reads state topics with
  // qos::state_observer_topic(timing), heartbeats with
  // qos::heartbeat_observer_topic(timing) and announcements with
  // qos::device_description_topic(timing), the only presets that match the
  // devices' writers.
  // Only these devices (uuid); empty = all.
  std::vector<std::string> device_filter;
  // Transport of the observer's participant: the network by default (as
  // EquipmentOptions::transport), qos::Transport::Loopback for this host only.
  qos::Transport transport = qos::Transport::Network;
  // The DDS implementation that observes (mtc/dds/middleware.hpp); it sees
  // equipment on any.
  Middleware middleware = Middleware::FastDds;
  // DDS-Security identity of the observer (a read-only one from
  // scripts/security/make-pki.sh); empty: unsecured.
  std::string security_dir;
  // The observer requests this liveliness lease from every heartbeat writer;
  // it must be at least the longest lease of the observed devices (a device
  // with a longer lease does not match, which the observer reports on
  // stderr). A device's loss is reported after its own lease. No DEADLINE is
  // requested, so devices with any heartbeat period match.
  qos::Timing timing;
  // false: every DDS event is handed to the observer's dispatch thread.
  // true: a received sample that finds the observer idle is handled, and its
  // callbacks run, at once on the middleware's receive thread: a thread
  // hand-off less between a device's write and the callback (the bridge's
  // DDS-to-client latency, docs/benchmarks.md). Statuses (matches, lost
  // writers, liveliness) are still handed over. Callbacks stay one at a
  // time and in order, but must not block: they hold up the receive thread.
  bool inline_steps = false;
};

class DomainObserver {
 public:
  // Creates participant, topics and readers; throws mtc::dds::Error (typed,
  // from the DDS return code) when any entity cannot be created.
  DomainObserver(const DomainObserverOptions& options, DomainObserverCallbacks callbacks);
  ~DomainObserver();
  DomainObserver(const DomainObserver&) = delete;
  DomainObserver& operator=(const DomainObserver&) = delete;

  // Devices announced so far (a copy, safe from any thread).
  std::vector<ObservedDevice> devices() const;
  // The DDS implementation the observer's participant runs on.
  Middleware middleware() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mtc::dds
