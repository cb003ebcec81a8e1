// DeviceModel from a user's MTConnectDevices file (1.3 .. 2.0). The file is
// checked for what the agent relies on (ids, uuids, data item types and
// categories, unique ids); anything else in it is served as written.
#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>

#include "mtc/bridge/device_model.hpp"

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

 private:
  std::string_view text_;
  const std::string& name_;
  std::set<std::string> ids_;
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

}  // namespace

DeviceModel DeviceModel::from_file(const std::string& path, SlotRegistry& slots) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ModelError(path, 0, "cannot open the Devices file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw ModelError(path, 0, "cannot read the Devices file");
  return from_text(text.str(), path, slots);
}

DeviceModel DeviceModel::from_text(std::string_view xml, const std::string& name,
                                   SlotRegistry& slots) {
  FileChecker check(xml, name);
  pugi::xml_document source;
  const pugi::xml_parse_result parsed = source.load_buffer(xml.data(), xml.size());
  if (!parsed)
    check.fail(parsed.offset, std::string("not well-formed XML: ") + parsed.description());

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
    check.check_component(dev);
    any_device = true;
  }
  if (!any_device) check.fail(devices, "<Devices> holds no <Device>");

  model.doc_.append_copy(devices);
  model.index(slots);
  return model;
}

}  // namespace mtc::bridge
