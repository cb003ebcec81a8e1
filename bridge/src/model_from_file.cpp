// DeviceModel from a user's MTConnectDevices file (1.3 .. 2.0). The file is
// checked for what the agent relies on (ids, uuids, data item types and
// categories, unique ids and devices) and for what would hurt it (size,
// nesting, DOCTYPE entities, text XML forbids); anything else in it is
// served as written.
#include <algorithm>
#include <cstring>
#include <iterator>
#include <map>
#include <set>

#include "mtc/bridge/bounded_file.hpp"
#include "mtc/bridge/device_model.hpp"
#include "mtc/bridge/xml_text.hpp"

namespace mtc::bridge {

namespace {

constexpr std::string_view kDevicesUrn = "urn:mtconnect.org:MTConnectDevices:";

class FileChecker {
 public:
  FileChecker(std::string_view text, const std::string& name) : text_(text), name_(name) {}

  [[noreturn]] void fail(std::ptrdiff_t offset, const std::string& reason) const {
    throw ModelError(name_, line_of(offset), reason);
  }
  [[noreturn]] void fail(pugi::xml_node node, const std::string& reason) const {
    fail(node.offset_debug(), reason);
  }

  std::size_t line_of(std::ptrdiff_t offset) const {
    if (offset < 0) return 0;
    const auto end = std::min<std::size_t>(static_cast<std::size_t>(offset), text_.size());
    return 1 + static_cast<std::size_t>(std::count(text_.begin(), text_.begin() + end, '\n'));
  }

  void require(pugi::xml_node node, const char* attribute) const {
    if (std::strlen(node.attribute(attribute).value()) == 0) {
      fail(node,
           std::string("<") + node.name() + "> lacks the required attribute '" + attribute + "'");
    }
  }

  const std::set<std::string>& ids() const { return ids_; }

  void check_id(pugi::xml_node node) {
    require(node, "id");
    if (!ids_.insert(node.attribute("id").value()).second) {
      fail(node, std::string("duplicate id '") + node.attribute("id").value() + "'");
    }
  }

  void check_component(pugi::xml_node node) {
    check_id(node);
    for (pugi::xml_node di : node.child("DataItems").children()) {
      if (di.type() != pugi::node_element) continue;
      if (std::string_view(di.name()) != "DataItem") {
        fail(di, std::string("unexpected <") + di.name() + "> in <DataItems>");
      }
      check_id(di);
      require(di, "type");
      if (!is_data_item_type(di.attribute("type").value())) {
        fail(di, std::string("DataItem type '") + di.attribute("type").value() +
                     "' is not an MTConnect type name (UPPER_CASE, optionally prefix:)");
      }
      require(di, "category");
      const std::string_view category = di.attribute("category").value();
      if (category != "SAMPLE" && category != "EVENT" && category != "CONDITION") {
        fail(di, "DataItem category must be SAMPLE, EVENT or CONDITION, not '" +
                     std::string(category) + "'");
      }
    }
    for (pugi::xml_node child : node.child("Components").children()) {
      if (child.type() == pugi::node_element) check_component(child);
    }
  }

  // Devices are found by name or uuid (/{device}, DDS uuids): each must
  // name one device only.
  // A device may use its uuid as its name; no other device may use either.
  void check_unique_device(pugi::xml_node device) {
    for (const char* attribute : {"uuid", "name"}) {
      const std::string value = device.attribute(attribute).value();
      const auto [it, inserted] = device_keys_.emplace(value, device.offset_debug());
      if (!inserted && it->second != device.offset_debug()) {
        fail(device, std::string("duplicate device ") + attribute + " '" + value +
                         "' (first on line " + std::to_string(line_of(it->second)) + ")");
      }
    }
  }

 private:
  std::string_view text_;
  const std::string& name_;
  std::set<std::string> ids_;
  std::map<std::string, std::ptrdiff_t> device_keys_;  // names and uuids -> offset
};

// Walks the whole parsed tree without recursion (pugixml's traverse keeps
// its own cursor) and refuses the first node nested deeper than the limit
// or holding text XML forbids; the recursive checks after it rely on both.
class TreeGuard : public pugi::xml_tree_walker {
 public:
  TreeGuard(const FileChecker& check, std::size_t max_depth) : check_(check), max_(max_depth) {}

  bool for_each(pugi::xml_node& node) override {
    // depth() counts from 0 at the document element's level.
    if (node.type() == pugi::node_element && static_cast<std::size_t>(depth()) + 1 > max_) {
      check_.fail(node, "elements nested deeper than " + std::to_string(max_) + " levels (<" +
                            node.name() + ">)");
    }
    check_text(node, node.name());
    check_text(node, node.value());
    for (pugi::xml_attribute a : node.attributes()) {
      check_text(node, a.name());
      check_text(node, a.value());
    }
    return true;
  }

 private:
  void check_text(pugi::xml_node node, std::string_view text) const {
    const std::size_t bad = find_unfit_xml_char(text);
    if (bad == std::string_view::npos) return;
    const auto byte = static_cast<unsigned char>(text[bad]);
    if (byte < 0x80) {
      check_.fail(node, "character U+00" + hex(byte) + " is not allowed in XML");
    }
    check_.fail(node, "text is not valid UTF-8 (byte 0x" + hex(byte) + ")");
  }
  static std::string hex(unsigned char byte) {
    constexpr const char* kDigits = "0123456789ABCDEF";
    return {kDigits[byte >> 4], kDigits[byte & 0xF]};
  }

  const FileChecker& check_;
  std::size_t max_;
};

// Removes `prefix:` from every element name (a document written with a
// prefixed MTConnect namespace), so XPath and the printer see plain names.
void strip_prefix(pugi::xml_node node, const std::string& prefix) {
  const std::string_view name = node.name();
  if (name.size() > prefix.size() && name.substr(0, prefix.size()) == prefix) {
    node.set_name(std::string(name.substr(prefix.size())).c_str());
  }
  for (pugi::xml_node c : node.children()) {
    if (c.type() == pugi::node_element) strip_prefix(c, prefix);
  }
}

// Parses `xml` into `source` and refuses, before anything recurses over
// it, what ModelLimits excludes, a DOCTYPE, and text XML forbids.
void parse_guarded(pugi::xml_document& source, std::string_view xml, FileChecker& check,
                   const ModelLimits& limits) {
  if (xml.size() > limits.max_file_bytes) {
    check.fail(
        0, "the Devices file is larger than " + std::to_string(limits.max_file_bytes) + " bytes");
  }
  // DOCTYPE kept as a node so that it can be refused by line: pugixml never
  // expands declared entities, but a document that declares them would be
  // served with the references unexpanded, i.e. not as written.
  const pugi::xml_parse_result parsed =
      source.load_buffer(xml.data(), xml.size(), pugi::parse_default | pugi::parse_doctype);
  if (!parsed) {
    check.fail(parsed.offset, std::string("not well-formed XML: ") + parsed.description());
  }
  for (pugi::xml_node top : source.children()) {
    if (top.type() == pugi::node_doctype) {
      check.fail(top, "DOCTYPE declarations (and the entities they declare) are not accepted");
    }
  }
  TreeGuard guard(check, limits.max_depth);
  source.traverse(guard);
}

// The <Devices> element, every device checked (ids, names, uuids, items).
pugi::xml_node checked_devices(pugi::xml_node root, FileChecker& check) {
  pugi::xml_node devices = root.child("Devices");
  if (!devices) check.fail(root, "<MTConnectDevices> has no <Devices> element");
  bool any_device = false;
  for (pugi::xml_node dev : devices.children()) {
    if (dev.type() != pugi::node_element) continue;
    const std::string_view dn = dev.name();
    if (dn != "Device" && dn != "Agent") {
      check.fail(dev, "unexpected <" + std::string(dn) + "> in <Devices>");
    }
    check.require(dev, "name");
    check.require(dev, "uuid");
    check.check_unique_device(dev);
    check.check_component(dev);
    any_device = true;
  }
  if (!any_device) check.fail(devices, "<Devices> holds no <Device>");
  return devices;
}

// Each Device gets the ASSET_CHANGED and ASSET_REMOVED items the reference
// agent adds to devices whose file lacks them. Ids: "<device id>_asset_chg"
// (made unique). The schemas want DataItems after Description and
// Configuration, before Components.
void add_asset_items(pugi::xml_node devices, const std::set<std::string>& used_ids) {
  std::set<std::string> ids = used_ids;
  for (pugi::xml_node dev : devices.children("Device")) {
    pugi::xml_node items = dev.child("DataItems");
    if (!items) {
      pugi::xml_node after =
          dev.child("Configuration") ? dev.child("Configuration") : dev.child("Description");
      items = after ? dev.insert_child_after("DataItems", after) : dev.prepend_child("DataItems");
    }
    for (const auto& [type, suffix] :
         {std::pair{"ASSET_CHANGED", "_asset_chg"}, std::pair{"ASSET_REMOVED", "_asset_rem"}}) {
      if (!items.find_child_by_attribute("DataItem", "type", type).empty()) continue;
      std::string id = std::string(dev.attribute("id").value()) + suffix;
      for (int n = 2; !ids.insert(id).second; ++n) {
        id = std::string(dev.attribute("id").value()) + suffix + "_" + std::to_string(n);
      }
      pugi::xml_node item = items.append_child("DataItem");
      item.append_attribute("category") = "EVENT";
      item.append_attribute("id") = id.c_str();
      item.append_attribute("type") = type;
    }
  }
}

}  // namespace

DeviceModel DeviceModel::from_file(const std::string& path, SlotRegistry& slots,
                                   const ModelLimits& limits) {
  std::string error;
  const auto text = read_bounded_file(path, limits.max_file_bytes, "the Devices file", error);
  if (!text) throw ModelError(path, 0, error);
  return from_text(*text, path, slots, limits);
}

DeviceModel DeviceModel::from_text(std::string_view xml, const std::string& name,
                                   SlotRegistry& slots, const ModelLimits& limits) {
  FileChecker check(xml, name);
  pugi::xml_document source;
  parse_guarded(source, xml, check, limits);

  pugi::xml_node root = source.document_element();
  std::string root_name = root.name();
  std::string prefix;
  if (const auto colon = root_name.find(':'); colon != std::string::npos) {
    prefix = root_name.substr(0, colon + 1);
    root_name = root_name.substr(colon + 1);
  }
  if (root_name != "MTConnectDevices") {
    check.fail(root, "the root element is <" + std::string(root.name()) +
                         ">, expected <MTConnectDevices>");
  }
  DeviceModel model;
  const std::string ns_attr =
      prefix.empty() ? "xmlns" : "xmlns:" + prefix.substr(0, prefix.size() - 1);
  const std::string_view urn = root.attribute(ns_attr.c_str()).value();
  if (urn.substr(0, kDevicesUrn.size()) == kDevicesUrn) {
    model.file_version_ = parse_schema_version(urn.substr(kDevicesUrn.size()));
  }
  for (pugi::xml_attribute a : root.attributes()) {
    const std::string_view an = a.name();
    if (an.substr(0, 6) != "xmlns:" || an == ns_attr || an == "xmlns:xsi") continue;
    if (std::string_view(a.value()).substr(0, 20) == "urn:mtconnect.org:MT") continue;
    model.extra_namespaces_.emplace_back(a.name(), a.value());
  }
  if (!prefix.empty()) strip_prefix(root, prefix);

  const pugi::xml_node devices = checked_devices(root, check);
  add_asset_items(model.doc_.append_copy(devices), check.ids());
  model.index(slots);
  return model;
}

}  // namespace mtc::bridge
