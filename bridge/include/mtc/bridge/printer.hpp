// XML printer: turns the model and observations into MTConnectDevices,
// MTConnectStreams, MTConnectError and MTConnectAssets documents for one
// schema version. Knows nothing of HTTP or locking; every document is built
// with pugixml and serialised once.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mtc/bridge/device_model.hpp"
#include "mtc/bridge/observation_buffer.hpp"
#include "mtc/bridge/schema_version.hpp"

namespace mtc::bridge {

struct HeaderInfo {
  std::uint64_t instance_id = 0;
  std::string sender;
  std::size_t buffer_size = 0;
  std::uint64_t first_sequence = 1;
  std::uint64_t last_sequence = 0;
  std::uint64_t next_sequence = 1;
  std::int64_t model_change_time_ns = 0;
  std::int64_t creation_time_ns = 0;
  std::size_t asset_buffer_size = 0;
  std::size_t asset_count = 0;
};

// One observation to print and the model item it belongs to.
struct StreamEntry {
  std::size_t item = 0;
  const Observation* observation = nullptr;
};

struct ErrorEntry {
  std::string_view code;  // schema errorCode, e.g. "OUT_OF_RANGE"
  std::string text;
};

class Printer {
 public:
  explicit Printer(SchemaVersion version) noexcept : version_(version) {}
  SchemaVersion version() const noexcept { return version_; }

  // /probe: the whole model or one device.
  std::string probe(const HeaderInfo& header, const DeviceModel& model,
                    std::optional<std::size_t> device, bool pretty = false) const;
  // /current and /sample: entries grouped into DeviceStream/ComponentStream
  // (model order), observations within a component in the given order. Every
  // device in scope gets a DeviceStream, even an empty one.
  std::string streams(const HeaderInfo& header, const DeviceModel& model,
                      std::optional<std::size_t> device, const std::vector<StreamEntry>& entries,
                      bool pretty = false) const;
  std::string error(const HeaderInfo& header, const std::vector<ErrorEntry>& errors,
                    bool pretty = false) const;
  // Empty MTConnectAssets document (the bridge stores no assets).
  std::string assets(const HeaderInfo& header, bool pretty = false) const;

 private:
  SchemaVersion version_;
};

// ISO 8601 UTC with microseconds: 2026-11-21T05:44:37.123456Z.
std::string format_timestamp(std::int64_t ns_since_epoch);
// ISO 8601 UTC to the second: 2026-11-21T05:44:37Z (header creationTime).
std::string format_creation_time(std::int64_t ns_since_epoch);

}  // namespace mtc::bridge
