#include "json_printer.hpp"

#include <algorithm>
#include <pugixml.hpp>
#include <string_view>

#include "json_writer.hpp"
#include "mtc/bridge/xml_text.hpp"

namespace mtc::bridge::detail {

namespace {

enum class HeaderKind { Probe, Streams, Error, Assets };

// The document's root object and its Header; the caller closes both
// objects after its body.
void open_document(JsonWriter& w, const char* root, const HeaderInfo& h, SchemaVersion v,
                   HeaderKind kind) {
  const std::string schema(to_string(v));
  w.begin_object().key(root).begin_object();
  w.member("jsonVersion", static_cast<std::uint64_t>(kJsonVersion));
  if (kind != HeaderKind::Error) w.member("schemaVersion", schema);
  w.key("Header").begin_object();
  w.member("version", header_version(v));
  w.member("creationTime", format_creation_time(h.creation_time_ns));
  w.key("testIndicator").boolean(false);
  w.member("instanceId", h.instance_id);
  w.member("sender", make_xml_safe(h.sender));
  w.member("schemaVersion", schema);
  if (kind != HeaderKind::Error && has_model_change_time(v)) {
    w.member("deviceModelChangeTime", format_timestamp(h.model_change_time_ns));
  }
  if (kind != HeaderKind::Assets) w.member("bufferSize", static_cast<std::uint64_t>(h.buffer_size));
  if (kind == HeaderKind::Streams) {
    w.member("nextSequence", h.next_sequence);
    w.member("lastSequence", h.last_sequence);
    w.member("firstSequence", h.first_sequence);
  }
  if (kind == HeaderKind::Probe || kind == HeaderKind::Assets) {
    w.member("assetBufferSize", static_cast<std::uint64_t>(h.asset_buffer_size));
    w.member("assetCount", static_cast<std::uint64_t>(h.asset_count));
  }
  w.end_object();
}

void close_document(JsonWriter& w) {
  w.end_object().end_object();
}

bool is_namespace_declaration(std::string_view name) {
  return name == "xmlns" || name.rfind("xmlns:", 0) == 0;
}

// A list element: a plural name and no attributes (Devices, DataItems,
// Components, References, Compositions, ...). Its children print as arrays.
bool is_list_element(pugi::xml_node e) {
  const std::string_view name = e.name();
  return !e.first_attribute() && name.size() > 1 && name.back() == 's';
}

std::string element_text(pugi::xml_node e) {
  std::string text;
  for (pugi::xml_node c : e.children()) {
    if (c.type() == pugi::node_pcdata || c.type() == pugi::node_cdata) text += c.value();
  }
  const auto begin = text.find_first_not_of(" \t\r\n");
  if (begin == std::string::npos) return {};
  return text.substr(begin, text.find_last_not_of(" \t\r\n") - begin + 1);
}

// Names of the element children of `e`, in order of first appearance.
std::vector<std::string_view> child_names(pugi::xml_node e) {
  std::vector<std::string_view> names;
  for (pugi::xml_node c : e.children()) {
    if (c.type() != pugi::node_element) continue;
    if (std::find(names.begin(), names.end(), std::string_view(c.name())) == names.end()) {
      names.emplace_back(c.name());
    }
  }
  return names;
}

void write_element(JsonWriter& w, pugi::xml_node e);

// The children of `e` named `name`: an array when `e` is a list or the
// name repeats, else one object.
void write_children(JsonWriter& w, pugi::xml_node e, std::string_view name) {
  std::size_t count = 0;
  for (pugi::xml_node c : e.children()) {
    if (c.type() == pugi::node_element && c.name() == name) ++count;
  }
  w.key(name);
  if (!is_list_element(e) && count == 1) {
    write_element(w, e.child(std::string(name).c_str()));
    return;
  }
  w.begin_array();
  for (pugi::xml_node c : e.children()) {
    if (c.type() == pugi::node_element && c.name() == name) write_element(w, c);
  }
  w.end_array();
}

void write_element(JsonWriter& w, pugi::xml_node e) {
  w.begin_object();
  for (pugi::xml_attribute a : e.attributes()) {
    if (!is_namespace_declaration(a.name())) w.member(a.name(), a.value());
  }
  const std::string text = element_text(e);
  if (!text.empty()) w.member("value", text);
  for (std::string_view name : child_names(e)) write_children(w, e, name);
  w.end_object();
}

const char* category_group(Category c) {
  switch (c) {
    case Category::Sample:
      return "Samples";
    case Category::Condition:
      return "Condition";
    case Category::Event:
      break;
  }
  return "Events";
}

std::string condition_element(std::string_view value) {
  if (value == "NORMAL") return "Normal";
  if (value == "WARNING") return "Warning";
  if (value == "FAULT") return "Fault";
  return "Unavailable";
}

std::string observation_element(const DataItemInfo& item, const Observation& o) {
  return item.category == Category::Condition ? condition_element(o.value) : item.element;
}

void write_observation(JsonWriter& w, const DataItemInfo& item, const Observation& o) {
  w.begin_object();
  w.member("dataItemId", item.id);
  w.member("timestamp", format_timestamp(o.time_ns));
  if (!item.name.empty()) w.member("name", item.name);
  w.member("sequence", o.sequence);
  if (!item.sub_type.empty()) w.member("subType", item.sub_type);
  if (item.category == Category::Condition) {
    w.member("type", item.type);
  } else if (item.category == Category::Sample && is_json_number(o.value)) {
    w.key("value").raw_number(o.value);
  } else {
    w.member("value", o.value);
  }
  w.end_object();
}

// Entries of one component, [begin, end): grouped by category, then by
// observation element, each group in sequence order (as the reference agent
// orders them).
void write_component_stream(JsonWriter& w, const DeviceModel& model,
                            std::vector<StreamEntry>::const_iterator begin,
                            std::vector<StreamEntry>::const_iterator end) {
  const auto& items = model.data_items();
  const ComponentInfo& comp = model.components()[items[begin->item].component];
  w.begin_object();
  w.member("component", comp.element);
  w.member("componentId", comp.id);
  if (!comp.name.empty()) w.member("name", comp.name);
  for (const Category category : {Category::Sample, Category::Event, Category::Condition}) {
    std::vector<std::pair<std::string, const StreamEntry*>> group;
    for (auto it = begin; it != end; ++it) {
      const DataItemInfo& item = items[it->item];
      if (item.category == category) {
        group.emplace_back(observation_element(item, *it->observation), &*it);
      }
    }
    if (group.empty()) continue;
    std::stable_sort(group.begin(), group.end(), [](const auto& a, const auto& b) {
      if (a.first != b.first) return a.first < b.first;
      return a.second->observation->sequence < b.second->observation->sequence;
    });
    w.key(category_group(category)).begin_object();
    for (std::size_t i = 0; i < group.size();) {
      w.key(group[i].first).begin_array();
      std::size_t j = i;
      for (; j < group.size() && group[j].first == group[i].first; ++j) {
        write_observation(w, items[group[j].second->item], *group[j].second->observation);
      }
      w.end_array();
      i = j;
    }
    w.end_object();
  }
  w.end_object();
}

}  // namespace

std::string JsonPrinter::probe(const HeaderInfo& h, const DeviceModel& model,
                               std::optional<std::size_t> device, bool pretty) const {
  std::string out;
  JsonWriter w(out, pretty);
  open_document(w, "MTConnectDevices", h, version_, HeaderKind::Probe);
  // The devices in scope, as the XML probe lists them.
  std::vector<pugi::xml_node> devices;
  std::size_t index = 0;
  for (pugi::xml_node dev : model.devices_node().children()) {
    if (dev.type() != pugi::node_element) continue;
    if (!device || *device == index) devices.push_back(dev);
    ++index;
  }
  w.key("Devices").begin_object();
  const bool agent_in_file = static_cast<bool>(model.devices_node().child("Agent"));
  if (requires_agent_device(version_) && !agent_in_file) {
    w.key("Agent").begin_array().begin_object();
    w.member("id", "mtc_bridge_agent").member("name", "Agent").member("uuid", h.sender + "-agent");
    w.end_object().end_array();
  }
  std::vector<std::string_view> names;
  for (pugi::xml_node dev : devices) {
    if (std::find(names.begin(), names.end(), std::string_view(dev.name())) == names.end()) {
      names.emplace_back(dev.name());
    }
  }
  for (std::string_view name : names) {
    w.key(name).begin_array();
    for (pugi::xml_node dev : devices) {
      if (dev.name() == name) write_element(w, dev);
    }
    w.end_array();
  }
  w.end_object();
  close_document(w);
  return out;
}

std::string JsonPrinter::streams(const HeaderInfo& h, const DeviceModel& model,
                                 std::optional<std::size_t> device,
                                 const std::vector<StreamEntry>& entries, bool pretty) const {
  const auto& items = model.data_items();
  std::vector<StreamEntry> sorted;
  sorted.reserve(entries.size());
  for (const StreamEntry& e : entries) {
    if (!device || items[e.item].device == *device) sorted.push_back(e);
  }
  std::stable_sort(sorted.begin(), sorted.end(), [&](const StreamEntry& a, const StreamEntry& b) {
    return items[a.item].component < items[b.item].component;
  });
  std::string out;
  out.reserve(256 + 200 * sorted.size());
  JsonWriter w(out, pretty);
  open_document(w, "MTConnectStreams", h, version_, HeaderKind::Streams);
  w.key("Streams").begin_object();
  if (!sorted.empty()) {
    w.key("DeviceStream").begin_array();
    for (auto it = sorted.begin(); it != sorted.end();) {
      const DeviceInfo& info = model.devices()[items[it->item].device];
      w.begin_object().member("name", info.name).member("uuid", info.uuid);
      w.key("ComponentStream").begin_array();
      const std::size_t d = items[it->item].device;
      while (it != sorted.end() && items[it->item].device == d) {
        const std::size_t comp = items[it->item].component;
        auto end = it;
        while (end != sorted.end() && items[end->item].component == comp) ++end;
        write_component_stream(w, model, it, end);
        it = end;
      }
      w.end_array().end_object();
    }
    w.end_array();
  }
  w.end_object();
  close_document(w);
  return out;
}

std::string JsonPrinter::error(const HeaderInfo& h, const std::vector<ErrorEntry>& errors,
                               bool pretty) const {
  std::string out;
  JsonWriter w(out, pretty);
  open_document(w, "MTConnectError", h, version_, HeaderKind::Error);
  w.key("Errors").begin_object().key("Error").begin_array();
  for (const ErrorEntry& e : errors) {
    // Error texts quote requests: any byte may be there once decoded.
    w.begin_object().member("errorCode", e.code).member("value", make_xml_safe(e.text));
    w.end_object();
  }
  w.end_array().end_object();
  close_document(w);
  return out;
}

std::string JsonPrinter::assets(const HeaderInfo& h, bool pretty) const {
  std::string out;
  JsonWriter w(out, pretty);
  open_document(w, "MTConnectAssets", h, version_, HeaderKind::Assets);
  w.key("Assets").begin_object().end_object();
  close_document(w);
  return out;
}

}  // namespace mtc::bridge::detail
