// Passive view of a DDS domain: every device's announcements and every
// interface data item, as plain values. Used by the bridge and by the
// `mtc watch` / `mtc list` commands; it never publishes anything.
//
// Threading: DDS listeners only copy samples into a queue; every callback
// below runs on the observer's single dispatch thread, in arrival order.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mtc/core/vocabulary.hpp"
#include "mtc/qos/participant.hpp"
#include "mtc/qos/timing.hpp"

namespace mtc::dds {

// Which kind of Part 5 data item a value belongs to.
enum class ItemKind : std::uint8_t { Interaction, InterfaceState, DoorState, ChuckState };

// One sample of one data item, in MTConnect spelling ("READY", "ENABLED").
struct ObservedValue {
  std::string device_uuid;
  std::string data_item_id;
  std::string interface_id;
  ItemKind kind = ItemKind::Interaction;
  std::optional<core::Service> service;   // set for Interaction items
  std::optional<core::SubType> sub_type;  // set for Interaction items
  std::string value;                      // MTConnect spelling of the state
  std::uint64_t sequence_number = 0;      // writer's change counter
  std::uint64_t heartbeat_count = 0;      // > 0: periodic repeat, not a change
  std::int64_t source_time_ns = 0;        // writer clock, ns since the epoch
  std::int64_t reception_time_ns = 0;     // local clock at reception
};

struct ObservedDataItem {
  std::string id;
  std::string name;
  std::string type;      // e.g. MATERIAL_LOAD, INTERFACE_STATE, DOOR_STATE
  std::string sub_type;  // REQUEST, RESPONSE or empty
  std::string category;  // EVENT
};

struct ObservedInterface {
  std::string id;
  std::string name;
  core::InterfaceType type = core::InterfaceType::MaterialHandler;
  std::vector<ObservedDataItem> data_items;
};

// A device's announcement (DeviceDescription topic).
struct ObservedDevice {
  std::string device_uuid;
  std::string name;
  std::vector<ObservedInterface> interfaces;
};

struct DomainObserverCallbacks {
  std::function<void(const ObservedDevice&)> on_device;
  std::function<void(const ObservedValue&)> on_value;
  // The writer(s) of these data items lost liveliness or were disposed:
  // their values must now read UNAVAILABLE.
  std::function<void(const std::string& device_uuid, const std::vector<std::string>& data_item_ids)>
      on_items_lost;
  // A device's announcement writer lost liveliness (device gone).
  std::function<void(const std::string& device_uuid)> on_device_lost;
};

struct DomainObserverOptions {
  int domain_id = 0;
  // Name of a QoS preset of mtc::qos for the state topics; empty = default.
  std::string qos_profile;
  // Only these devices (uuid); empty = all.
  std::vector<std::string> device_filter;
  // Transport of the observer's participant (loopback only by default).
  qos::Transport transport = qos::Transport::Loopback;
  // The observer requests this liveliness lease from every writer; it must
  // be at least the longest lease of the observed devices (a device with a
  // longer lease does not match, which the observer reports on stderr), and
  // it bounds how soon a lost device is reported. No DEADLINE is requested,
  // so devices with any heartbeat period match.
  qos::Timing timing;
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

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mtc::dds
