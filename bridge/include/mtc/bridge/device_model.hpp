// The agent's device model: the MTConnectDevices tree (kept as a pugixml
// document, so /probe copies it and `path` XPath runs on it) plus flat
// indexes of devices, components and data items for the streams printer.
//
// Built either from a user's Devices file (1.3 .. 2.0) or from the devices'
// DDS announcements. Each data item gets a `slot`: a stable index into the
// observation buffer's per-item state, handed out by a SlotRegistry that
// outlives model rebuilds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <pugixml.hpp>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mtc/bridge/model_error.hpp"
#include "mtc/bridge/model_limits.hpp"
#include "mtc/bridge/path_cost.hpp"
#include "mtc/bridge/schema_version.hpp"
#include "mtc/core/observation.hpp"

namespace mtc::bridge {

// Key of an item across rebuilds: (device uuid, item id as sent over DDS).
class SlotRegistry {
 public:
  std::uint32_t slot_for(const std::string& device_uuid, const std::string& item_id);
  std::size_t size() const noexcept { return next_; }

 private:
  std::map<std::pair<std::string, std::string>, std::uint32_t> slots_;
  std::uint32_t next_ = 0;
};

enum class Category : std::uint8_t { Sample, Event, Condition };

struct DataItemInfo {
  std::string id;         // XML id, unique in the document
  std::string source_id;  // id of the DDS data item it mirrors
  std::string name;
  std::string type;      // e.g. MATERIAL_LOAD
  std::string sub_type;  // REQUEST / RESPONSE / empty
  std::string element;   // streams element, e.g. MaterialLoad
  Category category = Category::Event;
  std::size_t device = 0;
  std::size_t component = 0;
  std::uint32_t slot = 0;
};

struct ComponentInfo {
  std::string id;
  std::string name;
  std::string element;  // e.g. "DoorInterface", "Device"
  std::size_t device = 0;
  // idRef of each References/DataItemRef: items defined elsewhere that an
  // interface uses (Part 5 1.6, 4.2.3.1), e.g. DOOR_STATE of a Door.
  std::vector<std::string> data_item_refs;
};

struct DeviceInfo {
  std::string id;
  std::string name;
  std::string uuid;
  std::optional<std::uint32_t> availability_slot;  // its AVAILABILITY item
};

// What a DDS data item is, to find its counterpart in a Devices file whose
// ids differ from the DDS ones.
struct ItemHint {
  std::string interface_id;
  std::string interface_element;  // e.g. "DoorInterface"; empty when unknown
  std::string type;               // e.g. MATERIAL_LOAD, INTERFACE_STATE
  std::string sub_type;           // REQUEST / RESPONSE / empty
};

class DeviceModel {
 public:
  DeviceModel();
  ~DeviceModel() = default;
  DeviceModel(const DeviceModel&) = delete;
  DeviceModel& operator=(const DeviceModel&) = delete;
  DeviceModel(DeviceModel&&) noexcept = default;
  DeviceModel& operator=(DeviceModel&&) noexcept = default;

  // Parses a Devices file; throws ModelError (file, line, reason). Refuses
  // what `limits` excludes, DOCTYPE declarations (no entity can expand),
  // text that XML forbids (invalid UTF-8, control characters), duplicate
  // ids, and devices sharing a name or uuid.
  static DeviceModel from_file(const std::string& path, SlotRegistry& slots,
                               const ModelLimits& limits = {});
  // Parses Devices XML held in memory; `name` is used in error messages.
  static DeviceModel from_text(std::string_view xml, const std::string& name, SlotRegistry& slots,
                               const ModelLimits& limits = {});
  // One Device per announcement, in the order given. Interface types the
  // version's Devices schema lacks (1.3: bar feeder, material handler) are
  // left out, with their items.
  static DeviceModel from_announcements(const std::vector<core::ObservedDevice>& devices,
                                        SchemaVersion version, SlotRegistry& slots);

  // Version named by the file's namespace, when it is one the agent knows.
  std::optional<SchemaVersion> file_version() const noexcept { return file_version_; }
  // The <Devices> element.
  pugi::xml_node devices_node() const { return doc_.document_element(); }
  // xmlns:* declarations of the file's root other than the MTConnect ones
  // (vendor extensions), to repeat on the probe root.
  const std::vector<std::pair<std::string, std::string>>& extra_namespaces() const {
    return extra_namespaces_;
  }

  const std::vector<DeviceInfo>& devices() const noexcept { return devices_; }
  const std::vector<ComponentInfo>& components() const noexcept { return components_; }
  const std::vector<DataItemInfo>& data_items() const noexcept { return items_; }

  // Device by name or uuid.
  std::optional<std::size_t> find_device(std::string_view name_or_uuid) const;
  // Item mirroring (device uuid, DDS item id); in a file model the DDS id is
  // the DataItem id. nullopt: the model lacks it.
  std::optional<std::size_t> find_item(const std::string& device_uuid,
                                       const std::string& source_id) const;
  std::optional<std::size_t> find_device_by_uuid(const std::string& uuid) const;
  // find_item, else the device's item that stands for this DDS item in a
  // Devices file written with other ids: the DataItem with id
  // "<device id or name>_<dds id>" (or '.' instead of '_'), else the only
  // DataItem of the device's *Interface components with the hint's type and
  // subType (narrowed by interface element, then by interface id); an item
  // an interface points at with References/DataItemRef counts as that
  // interface's. The answer is remembered; nullopt when there is none or it
  // is ambiguous.
  std::optional<std::size_t> resolve_item(const std::string& device_uuid,
                                          const std::string& source_id, const ItemHint& hint);

  // Data items (indexes, in model order) selected by an XPath over the
  // Devices tree: a DataItem node selects itself, any other element all
  // DataItems beneath it. `device` restricts the result to one device.
  // Throws std::invalid_argument for a malformed expression and for one
  // that `limits` refuses for this tree (estimate_path_cost), before
  // evaluating it.
  std::vector<std::size_t> select(const std::string& xpath, std::optional<std::size_t> device,
                                  const PathLimits& limits = {}) const;
  // The Devices tree's shape, for estimate_path_cost.
  const TreeShape& shape() const noexcept { return shape_; }
  // All items of one device or of every device, in model order.
  std::vector<std::size_t> all_items(std::optional<std::size_t> device) const;

 private:
  void index(SlotRegistry& slots);
  void index_component(pugi::xml_node node, std::size_t device, SlotRegistry& slots);
  std::vector<std::pair<std::size_t, std::size_t>> interface_candidates(std::size_t device,
                                                                        const ItemHint& hint) const;

  pugi::xml_document doc_;
  std::optional<SchemaVersion> file_version_;
  std::vector<std::pair<std::string, std::string>> extra_namespaces_;
  std::vector<DeviceInfo> devices_;
  std::vector<ComponentInfo> components_;
  std::vector<DataItemInfo> items_;
  std::unordered_map<std::string, std::size_t> item_by_xml_id_;
  std::map<std::pair<std::string, std::string>, std::size_t> item_by_source_;
  std::vector<bool> claimed_;  // items resolve_item() already gave away
  // Announcement models: XML id -> DDS item id where they differ.
  std::unordered_map<std::string, std::string> source_of_xml_id_;
  TreeShape shape_;
};

// SlotRegistry key (item id) of an announced device's AVAILABILITY item.
const std::string& availability_key();

// "MATERIAL_LOAD" -> "MaterialLoad"; vendor "x:FOO_BAR" -> "x:FooBar".
std::string element_name_for_type(std::string_view type);

}  // namespace mtc::bridge
