// The MTConnect agent of the bridge: device model + observation buffer +
// XML printer behind the `Agent` contract (agent.hpp).
//
// Construction and feeding (the bridge executable does this):
//
//   mtc::bridge::AgentOptions options;
//   options.devices_file = "cell.xml";   // or empty: model from announcements
//   auto agent = mtc::bridge::make_agent(options);   // throws ModelError
//   observer callbacks -> agent->add_device / add_value / items_lost /
//                         device_lost (from the DDS dispatch thread)
//   HTTP threads       -> agent->route / next_part / wait_for / subscribe
//
// Every member is thread-safe. Ingest calls take a writer lock for
// microseconds; rendering happens under a reader lock or from a cache.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "mtc/bridge/agent.hpp"
#include "mtc/bridge/model_error.hpp"
#include "mtc/bridge/model_limits.hpp"
#include "mtc/bridge/path_cost.hpp"
#include "mtc/bridge/schema_version.hpp"
#include "mtc/core/observation.hpp"

namespace mtc::bridge {

// Largest AgentOptions::buffer_size: 2^24 observations, about 1 GiB.
inline constexpr std::size_t kMaxBufferSize = std::size_t{1} << 24;

struct AgentOptions {
  // MTConnect schema version of every document. Unset: the version of the
  // Devices file when it names one of 1.3/1.6/1.8/2.0, otherwise 1.6 — the
  // only version whose official Devices, Streams and Error schemas all
  // accept the four Part 5 interface types (docs/bridge.md).
  std::optional<SchemaVersion> schema_version;
  // Observations kept for /sample. Any value from 2 to kMaxBufferSize (not
  // only powers of two); each takes about 60 bytes, allocated at start.
  std::size_t buffer_size = 131072;
  // MTConnectDevices file mapped onto the DDS data items. Empty: the model is
  // built from the devices' DDS announcements and grows as they appear.
  std::string devices_file;
  // What the Devices file may demand (size, nesting); see ModelLimits.
  ModelLimits devices_limits;
  // What a request's `path` XPath may cost (length, nesting, estimated node
  // visits); a path over them is refused with INVALID_PATH before it runs.
  PathLimits path_limits;
  // Devices accepted from DDS announcements. Anyone on an unsecured domain
  // may announce: beyond this, a new device takes the place of one that has
  // left (lost longest ago), or is refused (a warning says so).
  std::size_t max_announced_devices = 256;
  // Header sender attribute.
  std::string sender = "mtc-bridge";
  // Header instanceId; 0 = seconds since the epoch at construction, so every
  // start gets a new one.
  std::uint64_t instance_id = 0;
  // Largest count a /sample may ask for; 0 = buffer_size.
  std::size_t max_count = 0;
  // Largest /sample document, in bytes (estimated per observation before
  // printing). A sample that would be larger stops short: its nextSequence
  // tells the client where to go on, as for any sample. Bounds the memory
  // each answer takes (the whole default buffer would print as ~25 MiB).
  std::size_t max_document_bytes = std::size_t{4} << 20;
  // Observations a /sample returns when the request names no count, as
  // MTConnect agents do (never more than max_count).
  std::size_t default_count = 100;
  // Time without news before a stream sends an empty part, when the request
  // names no heartbeat (MTConnect agents: 10 s).
  std::chrono::milliseconds stream_heartbeat{10000};
  // Told (once per DDS item, on the ingest thread, no lock held) about
  // values the Devices file has no item for, naming device uuid, interface
  // and item: "DDS values of device 'cell-machine' interface 'door' item
  // 'door_foo' are dropped: no DataItem of cell.xml maps to them ...".
  // Empty: silent (stats() still counts). mtc-bridge logs them on stderr.
  std::function<void(const std::string&)> on_warning;
};

// Ingest counters, for logs and tests.
struct AgentStats {
  std::uint64_t observations = 0;    // observations appended
  std::uint64_t duplicates = 0;      // values equal to the latest (heartbeats)
  std::uint64_t unknown_values = 0;  // values for items not in the model
  std::uint64_t model_changes = 0;   // model rebuilds after announcements
  std::string last_unknown;          // "<device_uuid>/<data_item_id>"
  // /sample stream parts: rendered, and served to another stream at the
  // same position from the first one's rendering; the bytes such shared
  // parts hold now (bounded, whatever the number of streams or queries).
  std::uint64_t stream_parts_rendered = 0;
  std::uint64_t stream_parts_shared = 0;
  std::size_t shared_part_bytes = 0;
};

// One observation of a data item, as an adapter (SHDR) passes it on.
struct ItemObservation {
  std::uint64_t sequence = 0;
  std::int64_t time_ns = 0;
  std::string item;  // the data item's id in the Devices model (probe)
  std::string value;
  bool condition = false;  // CONDITION category: value is the level
};

class MtconnectAgent : public Agent {
 public:
  ~MtconnectAgent() override = default;

  // --- ingest: called from the DDS dispatch thread (any thread is safe) ---
  // A device's announcement. Without a Devices file, a new or changed
  // announcement rebuilds the model (deviceModelChangeTime moves). Either
  // way the device's AVAILABILITY item (if any) becomes AVAILABLE. With a
  // Devices file, an announcement maps onto a file device of the same uuid,
  // or of the same name when no other announcement claimed it first; it
  // never changes the file's model. Beyond max_announced_devices, refused
  // unless a device that left makes room.
  virtual void add_device(const core::ObservedDevice& device) = 0;
  // One value. Appended only when it differs from the item's latest value
  // (an unchanged value, e.g. the last one handed over again after a loss,
  // is dropped). Values for items the model lacks are
  // counted in stats() and dropped.
  virtual void add_value(const core::ObservedValue& value) = 0;
  // The heartbeats that vouch for these items stopped: each reads UNAVAILABLE.
  virtual void items_lost(const std::string& device_uuid,
                          const std::vector<std::string>& data_item_ids) = 0;
  // The device's announcement writer is gone: every item of the device,
  // including AVAILABILITY, reads UNAVAILABLE. It stays in the model until
  // a new device needs its place (max_announced_devices).
  virtual void device_lost(const std::string& device_uuid) = 0;

  // --- observations by item (the SHDR adapter) ---
  // The latest observation of every data item, in model order; `next` is
  // the sequence the next change will have.
  virtual std::vector<ItemObservation> latest_observations(std::uint64_t& next) const = 0;
  // Up to `max` observations from sequence `from` on, appended to `out`;
  // `next` is where to go on. False when `from` was overwritten (the
  // reader fell behind the buffer).
  virtual bool observations_since(std::uint64_t from, std::size_t max,
                                  std::vector<ItemObservation>& out, std::uint64_t& next) const = 0;

  virtual AgentStats stats() const = 0;
  virtual SchemaVersion schema_version() const noexcept = 0;
  virtual std::uint64_t instance_id() const noexcept = 0;
};

// Builds the agent. Throws ModelError for an unusable Devices file and
// std::invalid_argument for unusable options (buffer_size outside
// 2..kMaxBufferSize, default_count 0, stream_heartbeat not positive) and
// for a buffer the machine cannot allocate (never std::bad_alloc).
std::unique_ptr<MtconnectAgent> make_agent(const AgentOptions& options);

}  // namespace mtc::bridge
