// MTConnect JSON printer: the documents of printer.hpp in the JSON layout
// the MTConnect reference agent (cppagent 2.x) emits by default, its "JSON
// version 2":
//
//   {"MTConnectStreams": {"jsonVersion": 2, "schemaVersion": "1.6",
//     "Header": {..., "instanceId": 1, "nextSequence": 9, ...},
//     "Streams": {"DeviceStream": [{"name": ..., "uuid": ...,
//       "ComponentStream": [{"component": ..., "componentId": ...,
//         "Events": {"MaterialLoad": [{"dataItemId": ..., "sequence": 7,
//                                      "timestamp": ..., "value": "READY"}]}}]}]}}}
//
// Elements of one name become an array under that name; a list element
// (Devices, DataItems, Components, References, ...) becomes an object of
// such arrays; attributes become members (strings, as written in the XML;
// header counters and sequences are numbers) and element text `value`.
// Sample values that are numbers print as numbers. Internal to mtc_bridge.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "mtc/bridge/printer.hpp"

namespace mtc::bridge::detail {

// The reference agent's default JsonVersion.
inline constexpr int kJsonVersion = 2;

class JsonPrinter {
 public:
  explicit JsonPrinter(SchemaVersion version) noexcept : version_(version) {}

  std::string probe(const HeaderInfo& header, const DeviceModel& model,
                    std::optional<std::size_t> device, bool pretty = false) const;
  // As Printer::streams, except that, as the reference agent does, only
  // devices with observations get a DeviceStream ("Streams": {} when none).
  std::string streams(const HeaderInfo& header, const DeviceModel& model,
                      std::optional<std::size_t> device, const std::vector<StreamEntry>& entries,
                      bool pretty = false) const;
  std::string error(const HeaderInfo& header, const std::vector<ErrorEntry>& errors,
                    bool pretty = false) const;
  std::string assets(const HeaderInfo& header, bool pretty = false) const;

 private:
  SchemaVersion version_;
};

}  // namespace mtc::bridge::detail
