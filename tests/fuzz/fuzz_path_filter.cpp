// Fuzz target: the XPath `path` filter of /current and /sample. The bytes
// are the expression (after %-decoding, as the route table hands it on),
// run against the sample cell's Devices model: first its cost estimate
// (estimate_path_cost), then DeviceModel::select, which refuses a malformed
// or too costly expression with std::invalid_argument and must do nothing
// else: no other exception, no crash, no unbounded run.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "fuzz_support.hpp"
#include "mtc/bridge/device_model.hpp"
#include "mtc/bridge/path_cost.hpp"

namespace {

const mtc::bridge::DeviceModel& model() {
  static mtc::bridge::SlotRegistry slots;
  static const auto instance = mtc::bridge::DeviceModel::from_file(MTC_FUZZ_DEVICES_FILE, slots);
  return instance;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mtc::fuzz::ByteReader input(data, size);
  // First byte: all devices, or one of them (as /{device}/current asks).
  const std::uint8_t pick = input.byte();
  const std::string xpath(input.rest());
  const auto& devices = model().devices();
  std::optional<std::size_t> device;
  if (pick % (devices.size() + 1) != 0) device = pick % (devices.size() + 1) - 1;

  const mtc::bridge::PathLimits limits;
  const auto cost = mtc::bridge::estimate_path_cost(xpath, model().shape(), limits);
  mtc::fuzz::require(cost.accepted == cost.error.empty(), "a refusal must say why", cost.error);
  try {
    const auto items = model().select(xpath, device, limits);
    mtc::fuzz::require(cost.accepted, "select ran a path the estimate refused", xpath);
    for (const std::size_t index : items) {
      mtc::fuzz::require(index < model().data_items().size(), "select gave no item index");
      if (device) {
        mtc::fuzz::require(model().data_items()[index].device == *device,
                           "select left the device it was restricted to");
      }
    }
  } catch (const std::invalid_argument&) {
    // A malformed or refused expression: the agent answers INVALID_PATH.
  }
  return 0;
}
