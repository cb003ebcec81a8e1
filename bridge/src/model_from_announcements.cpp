// DeviceModel from the devices' DDS announcements: one Device per
// announcement, holding AVAILABILITY, ASSET_CHANGED and ASSET_REMOVED items
// and an Interfaces component
// with one *Interface component per announced interface. The agent hands
// announcements over with their text already fit for XML (make_xml_safe).
#include <cctype>
#include <map>
#include <string>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include "mtc/bridge/device_model.hpp"
#include "mtc/bridge/xml_text.hpp"

namespace mtc::bridge {

namespace {

// Key under which a device's AVAILABILITY item is registered; no DDS data
// item id can start with a control character.
const std::string kAvailabilityKey =
    "\x01"
    "availability";
const std::string kAssetChangedKey =
    "\x01"
    "asset_changed";
const std::string kAssetRemovedKey =
    "\x01"
    "asset_removed";

// Makes `text` a valid xs:ID (NCName) that no other element uses.
class IdMaker {
 public:
  std::string make(const std::string& text, const std::string& fallback) {
    std::string id = text.empty() ? fallback : text;
    for (char& c : id) {
      const auto uc = static_cast<unsigned char>(c);
      if (std::isalnum(uc) == 0 && c != '_' && c != '-' && c != '.') c = '_';
    }
    const auto first = static_cast<unsigned char>(id.front());
    if (std::isalpha(first) == 0 && id.front() != '_') id.insert(0, "_");
    std::string unique = id;
    for (int n = 2; !used_.insert(unique).second; ++n) unique = id + "_" + std::to_string(n);
    return unique;
  }

 private:
  std::unordered_set<std::string> used_;
};

// DDS ids are unique per device only, XML ids per document. An interface or
// item id that several devices use is qualified with the device id on every
// one of them, so the result does not depend on announcement order.
std::map<std::string, int> count_ids(const std::vector<core::ObservedDevice>& devices) {
  std::map<std::string, int> uses;
  for (const core::ObservedDevice& d : devices) {
    for (const core::ObservedInterface& itf : d.interfaces) {
      ++uses[itf.id];
      for (const core::ObservedDataItem& di : itf.data_items) ++uses[di.id];
    }
  }
  return uses;
}

// One announced data item as a DataItem element with id `xml_id`.
void append_data_item(pugi::xml_node items, const core::ObservedDataItem& di,
                      const std::string& xml_id) {
  pugi::xml_node node = items.append_child("DataItem");
  const bool known_category =
      di.category == "SAMPLE" || di.category == "EVENT" || di.category == "CONDITION";
  node.append_attribute("category") = known_category ? di.category.c_str() : "EVENT";
  node.append_attribute("id") = xml_id.c_str();
  if (!di.name.empty()) node.append_attribute("name") = di.name.c_str();
  node.append_attribute("type") = di.type.c_str();
  if (!di.sub_type.empty()) node.append_attribute("subType") = di.sub_type.c_str();
}

// AVAILABILITY, and the asset items every device of the reference agent
// has (the bridge keeps no assets: they read UNAVAILABLE), each mapped in
// `source_of` to the key its values arrive under.
void append_device_items(pugi::xml_node dev, const std::string& dev_id, IdMaker& ids,
                         std::unordered_map<std::string, std::string>& source_of) {
  pugi::xml_node device_items = dev.append_child("DataItems");
  for (const auto& [suffix, type, key] :
       {std::tuple{"_avail", "AVAILABILITY", &kAvailabilityKey},
        std::tuple{"_asset_chg", "ASSET_CHANGED", &kAssetChangedKey},
        std::tuple{"_asset_rem", "ASSET_REMOVED", &kAssetRemovedKey}}) {
    pugi::xml_node item = device_items.append_child("DataItem");
    const std::string item_id = ids.make(dev_id + suffix, "item");
    item.append_attribute("category") = "EVENT";
    item.append_attribute("id") = item_id.c_str();
    item.append_attribute("type") = type;
    source_of[item_id] = *key;
  }
}

}  // namespace

DeviceModel DeviceModel::from_announcements(const std::vector<core::ObservedDevice>& devices,
                                            SchemaVersion version, SlotRegistry& slots) {
  DeviceModel model;
  IdMaker ids;
  const std::map<std::string, int> uses = count_ids(devices);
  pugi::xml_node root = model.doc_.append_child("Devices");
  for (const core::ObservedDevice& announced : devices) {
    const std::string& name = announced.name.empty() ? announced.device_uuid : announced.name;
    pugi::xml_node dev = root.append_child("Device");
    const std::string dev_id = ids.make(name, "device");
    dev.append_attribute("id") = dev_id.c_str();
    dev.append_attribute("name") = name.c_str();
    dev.append_attribute("uuid") = announced.device_uuid.c_str();

    append_device_items(dev, dev_id, ids, model.source_of_xml_id_);
    auto qualified = [&](const std::string& id) {
      const auto it = uses.find(id);
      if (it == uses.end() || it->second <= 1) return id;
      std::string unique = dev_id;
      unique += '_';
      unique += id;
      return unique;
    };
    pugi::xml_node interfaces;
    for (const core::ObservedInterface& itf : announced.interfaces) {
      const std::string_view element = core::element_name(itf.type);
      if (!devices_schema_has(version, element)) continue;
      if (!interfaces) {
        interfaces = dev.append_child("Components").append_child("Interfaces");
        interfaces.append_attribute("id") = ids.make(dev_id + "_interfaces", "interfaces").c_str();
        interfaces = interfaces.append_child("Components");
      }
      pugi::xml_node comp = interfaces.append_child(std::string(element).c_str());
      comp.append_attribute("id") = ids.make(qualified(itf.id), "interface").c_str();
      if (!itf.name.empty()) comp.append_attribute("name") = itf.name.c_str();
      pugi::xml_node items;
      for (const core::ObservedDataItem& di : itf.data_items) {
        // A type or subType that is not an MTConnect name would print as a
        // broken element or an attribute no schema accepts: left out.
        if (di.id.empty() || !is_data_item_type(di.type)) continue;
        if (!di.sub_type.empty() && !is_data_item_type(di.sub_type)) continue;
        if (!items) items = comp.append_child("DataItems");
        const std::string xml_id = ids.make(qualified(di.id), "item");
        append_data_item(items, di, xml_id);
        if (xml_id != di.id) model.source_of_xml_id_[xml_id] = di.id;
      }
    }
  }
  model.index(slots);
  return model;
}

const std::string& availability_key() {
  return kAvailabilityKey;
}

}  // namespace mtc::bridge
