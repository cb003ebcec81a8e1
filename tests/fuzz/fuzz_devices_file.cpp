// Fuzz target: the Devices file loader. The bytes are the file's text;
// DeviceModel::from_text either builds a model whose indexes agree with
// each other or throws ModelError naming the file. Nothing else: no other
// exception, no crash (a deep file once overflowed the stack), no hang.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "fuzz_support.hpp"
#include "mtc/bridge/device_model.hpp"
#include "mtc/bridge/model_error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  mtc::bridge::SlotRegistry slots;
  try {
    auto model = mtc::bridge::DeviceModel::from_text(text, "fuzz.xml", slots);
    const auto& devices = model.devices();
    for (std::size_t i = 0; i < devices.size(); ++i) {
      const auto found = model.find_device_by_uuid(devices[i].uuid);
      mtc::fuzz::require(found && *found == i, "a device is not found by its uuid",
                         devices[i].uuid);
    }
    for (const auto& item : model.data_items()) {
      mtc::fuzz::require(item.device < devices.size(), "an item names no device", item.id);
      mtc::fuzz::require(item.slot < slots.size(), "an item has no slot", item.id);
      const auto found = model.find_item(devices[item.device].uuid, item.source_id);
      mtc::fuzz::require(found.has_value(), "an item is not found by its id", item.id);
    }
    // The whole tree through the path filter, as /current?path=//DataItem.
    for (const std::size_t index : model.select("//DataItem", std::nullopt)) {
      mtc::fuzz::require(index < model.data_items().size(), "select gave no item index");
    }
  } catch (const std::invalid_argument&) {
    // //DataItem over the estimate's limit for this tree: refused, not run.
  } catch (const mtc::bridge::ModelError& error) {
    mtc::fuzz::require(error.file() == "fuzz.xml", "the error names another file", error.what());
  }
  return 0;
}
