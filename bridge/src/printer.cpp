#include "mtc/bridge/printer.hpp"

#include <algorithm>
#include <ctime>
#include <pugixml.hpp>

#include "mtc/bridge/xml_text.hpp"

namespace mtc::bridge {

namespace {

constexpr const char* kXsi = "http://www.w3.org/2001/XMLSchema-instance";

class StringWriter : public pugi::xml_writer {
 public:
  explicit StringWriter(std::string& out) : out_(out) {}
  void write(const void* data, std::size_t size) override {
    out_.append(static_cast<const char*>(data), size);
  }

 private:
  std::string& out_;
};

std::tm utc_tm(std::int64_t ns, std::int64_t& micros) {
  std::int64_t secs = ns / 1000000000;
  std::int64_t rem = ns % 1000000000;
  if (rem < 0) {
    rem += 1000000000;
    --secs;
  }
  micros = rem / 1000;
  const auto t = static_cast<std::time_t>(secs);
  std::tm tm{};
  gmtime_r(&t, &tm);
  return tm;
}

std::string serialise(pugi::xml_document& doc, bool pretty) {
  std::string out;
  out.reserve(4096);
  StringWriter writer(out);
  const unsigned flags =
      (pretty ? pugi::format_indent : pugi::format_raw) | pugi::format_no_declaration;
  out.append("<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
  if (pretty) out.push_back('\n');
  doc.save(writer, "  ", flags, pugi::encoding_utf8);
  return out;
}

// Root element with the namespaces real agents emit, e.g.
// urn:mtconnect.org:MTConnectStreams:1.6 with its schemaLocation.
pugi::xml_node make_root(pugi::xml_document& doc, const char* kind, SchemaVersion v) {
  const std::string version(to_string(v));
  const std::string urn = std::string("urn:mtconnect.org:") + kind + ":" + version;
  pugi::xml_node root = doc.append_child(kind);
  root.append_attribute("xmlns:m") = urn.c_str();
  root.append_attribute("xmlns") = urn.c_str();
  root.append_attribute("xmlns:xsi") = kXsi;
  const std::string location =
      urn + " http://schemas.mtconnect.org/schemas/" + kind + "_" + version + ".xsd";
  root.append_attribute("xsi:schemaLocation") = location.c_str();
  return root;
}

pugi::xml_node make_header(pugi::xml_node root, const HeaderInfo& h, SchemaVersion v,
                           bool model_time) {
  pugi::xml_node header = root.append_child("Header");
  header.append_attribute("creationTime") = format_creation_time(h.creation_time_ns).c_str();
  header.append_attribute("sender") = make_xml_safe(h.sender).c_str();
  header.append_attribute("instanceId") = static_cast<unsigned long long>(h.instance_id);
  header.append_attribute("version") = std::string(header_version(v)).c_str();
  if (model_time && has_model_change_time(v)) {
    header.append_attribute("deviceModelChangeTime") =
        format_timestamp(h.model_change_time_ns).c_str();
  }
  return header;
}

void add_sequences(pugi::xml_node header, const HeaderInfo& h) {
  header.append_attribute("bufferSize") = static_cast<unsigned long long>(h.buffer_size);
  header.append_attribute("nextSequence") = static_cast<unsigned long long>(h.next_sequence);
  header.append_attribute("firstSequence") = static_cast<unsigned long long>(h.first_sequence);
  header.append_attribute("lastSequence") = static_cast<unsigned long long>(h.last_sequence);
}

std::string condition_element(std::string_view value) {
  if (value == "NORMAL") return "Normal";
  if (value == "WARNING") return "Warning";
  if (value == "FAULT") return "Fault";
  return "Unavailable";
}

void add_observation(pugi::xml_node parent, const DataItemInfo& item, const Observation& o) {
  const bool condition = item.category == Category::Condition;
  pugi::xml_node e =
      parent.append_child(condition ? condition_element(o.value).c_str() : item.element.c_str());
  e.append_attribute("dataItemId") = item.id.c_str();
  e.append_attribute("timestamp") = format_timestamp(o.time_ns).c_str();
  if (!item.name.empty()) e.append_attribute("name") = item.name.c_str();
  e.append_attribute("sequence") = static_cast<unsigned long long>(o.sequence);
  if (!item.sub_type.empty()) e.append_attribute("subType") = item.sub_type.c_str();
  // Required by the 2.0 schema; the bridge keeps no assets, so no type.
  if (item.type == "ASSET_CHANGED" || item.type == "ASSET_REMOVED") {
    e.append_attribute("assetType") = "";
  }
  if (condition) {
    e.append_attribute("type") = item.type.c_str();
  } else {
    e.text().set(o.value.c_str());
  }
}

// The Device that stands for the bridge before any device is known.
DeviceInfo stand_in_device(const HeaderInfo& h) {
  DeviceInfo info;
  info.id = "mtc_bridge";
  info.name = h.sender;
  info.uuid = h.sender + "-bridge";
  return info;
}

pugi::xml_node add_device_stream(pugi::xml_node streams, const DeviceInfo& info) {
  pugi::xml_node ds = streams.append_child("DeviceStream");
  ds.append_attribute("name") = info.name.c_str();
  ds.append_attribute("uuid") = info.uuid.c_str();
  return ds;
}

// One ComponentStream from entries[begin, end) (all of one component).
void add_component_stream(pugi::xml_node device_stream, const DeviceModel& model,
                          const std::vector<StreamEntry>& entries, std::size_t begin,
                          std::size_t end) {
  const DataItemInfo& first = model.data_items()[entries[begin].item];
  const ComponentInfo& comp = model.components()[first.component];
  pugi::xml_node cs = device_stream.append_child("ComponentStream");
  cs.append_attribute("component") = comp.element.c_str();
  if (!comp.name.empty()) cs.append_attribute("name") = comp.name.c_str();
  cs.append_attribute("componentId") = comp.id.c_str();
  constexpr std::pair<Category, const char*> kGroups[] = {{Category::Sample, "Samples"},
                                                          {Category::Event, "Events"},
                                                          {Category::Condition, "Condition"}};
  for (const auto& [category, group_name] : kGroups) {
    pugi::xml_node group;
    for (std::size_t i = begin; i < end; ++i) {
      const DataItemInfo& item = model.data_items()[entries[i].item];
      if (item.category != category) continue;
      if (!group) group = cs.append_child(group_name);
      add_observation(group, item, *entries[i].observation);
    }
  }
}

// Hand-rolled: timestamps are printed for every observation of every
// document, and snprintf dominated the /current render cost.
void put_digits(char* out, long long value, int width) {
  for (int i = width - 1; i >= 0; --i) {
    out[i] = static_cast<char>('0' + value % 10);
    value /= 10;
  }
}

std::string format_time(std::int64_t ns, bool with_micros) {
  std::int64_t micros = 0;
  const std::tm tm = utc_tm(ns, micros);
  char buf[28] = "0000-00-00T00:00:00.000000Z";
  put_digits(buf, tm.tm_year + 1900LL, 4);
  put_digits(buf + 5, tm.tm_mon + 1LL, 2);
  put_digits(buf + 8, tm.tm_mday, 2);
  put_digits(buf + 11, tm.tm_hour, 2);
  put_digits(buf + 14, tm.tm_min, 2);
  put_digits(buf + 17, tm.tm_sec, 2);
  if (!with_micros) {
    buf[19] = 'Z';
    return std::string(buf, 20);
  }
  put_digits(buf + 20, micros, 6);
  return std::string(buf, 27);
}

}  // namespace

std::string format_timestamp(std::int64_t ns) {
  return format_time(ns, true);
}

std::string format_creation_time(std::int64_t ns) {
  return format_time(ns, false);
}

std::string Printer::probe(const HeaderInfo& h, const DeviceModel& model,
                           std::optional<std::size_t> device, bool pretty) const {
  pugi::xml_document doc;
  pugi::xml_node root = make_root(doc, "MTConnectDevices", version_);
  for (const auto& [name, value] : model.extra_namespaces()) {
    root.append_attribute(name.c_str()) = value.c_str();
  }
  pugi::xml_node header = make_header(root, h, version_, true);
  header.append_attribute("assetBufferSize") = static_cast<unsigned long long>(h.asset_buffer_size);
  header.append_attribute("assetCount") = static_cast<unsigned long long>(h.asset_count);
  header.append_attribute("bufferSize") = static_cast<unsigned long long>(h.buffer_size);
  pugi::xml_node devices = root.append_child("Devices");
  if (requires_agent_device(version_) && !model.devices_node().child("Agent")) {
    pugi::xml_node agent = devices.append_child("Agent");
    agent.append_attribute("id") = "mtc_bridge_agent";
    agent.append_attribute("name") = "Agent";
    agent.append_attribute("uuid") = make_xml_safe(h.sender + "-agent").c_str();
  }
  std::size_t index = 0;
  for (pugi::xml_node dev : model.devices_node().children()) {
    if (dev.type() != pugi::node_element) continue;
    if (!device || *device == index) devices.append_copy(dev);
    ++index;
  }
  if (!devices.child("Device")) {
    // Before any device is known: every schema wants a Device. The bridge
    // stands in, with no data items (nothing of it is streamed).
    const DeviceInfo info = stand_in_device(h);
    pugi::xml_node bridge = devices.append_child("Device");
    bridge.append_attribute("id") = info.id.c_str();
    bridge.append_attribute("name") = info.name.c_str();
    bridge.append_attribute("uuid") = info.uuid.c_str();
  }
  return serialise(doc, pretty);
}

std::string Printer::streams(const HeaderInfo& h, const DeviceModel& model,
                             std::optional<std::size_t> device,
                             const std::vector<StreamEntry>& entries, bool pretty) const {
  // Group by (device, component) in model order, keeping the given order
  // inside each group.
  std::vector<StreamEntry> sorted(entries);
  const auto& items = model.data_items();
  std::stable_sort(sorted.begin(), sorted.end(), [&](const StreamEntry& a, const StreamEntry& b) {
    return items[a.item].component < items[b.item].component;
  });

  pugi::xml_document doc;
  pugi::xml_node root = make_root(doc, "MTConnectStreams", version_);
  add_sequences(make_header(root, h, version_, true), h);
  pugi::xml_node streams = root.append_child("Streams");
  std::size_t next = 0;
  for (std::size_t d = 0; d < model.devices().size(); ++d) {
    if (device && *device != d) continue;
    while (next < sorted.size() && items[sorted[next].item].device < d) ++next;
    // As the reference agent: a device with nothing to show has no
    // DeviceStream (filtered /current, stream heartbeats), except that the
    // 1.3 schema wants at least one.
    if (next == sorted.size() || items[sorted[next].item].device != d) continue;
    pugi::xml_node ds = add_device_stream(streams, model.devices()[d]);
    while (next < sorted.size() && items[sorted[next].item].device == d) {
      std::size_t end = next + 1;
      const std::size_t comp = items[sorted[next].item].component;
      while (end < sorted.size() && items[sorted[end].item].component == comp) ++end;
      add_component_stream(ds, model, sorted, next, end);
      next = end;
    }
  }
  const std::size_t first = device.value_or(0);
  if (version_ == SchemaVersion::V1_3 && !streams.first_child()) {
    add_device_stream(streams,
                      first < model.devices().size() ? model.devices()[first] : stand_in_device(h));
  }
  return serialise(doc, pretty);
}

std::string Printer::error(const HeaderInfo& h, const std::vector<ErrorEntry>& errors,
                           bool pretty) const {
  pugi::xml_document doc;
  pugi::xml_node root = make_root(doc, "MTConnectError", version_);
  pugi::xml_node header = make_header(root, h, version_, false);
  header.append_attribute("bufferSize") = static_cast<unsigned long long>(h.buffer_size);
  pugi::xml_node list = root.append_child("Errors");
  for (const ErrorEntry& e : errors) {
    pugi::xml_node node = list.append_child("Error");
    node.append_attribute("errorCode") = std::string(e.code).c_str();
    // Error texts quote requests (a URL may carry any byte once decoded).
    node.text().set(make_xml_safe(e.text).c_str());
  }
  return serialise(doc, pretty);
}

std::string Printer::assets(const HeaderInfo& h, bool pretty) const {
  pugi::xml_document doc;
  pugi::xml_node root = make_root(doc, "MTConnectAssets", version_);
  pugi::xml_node header = make_header(root, h, version_, true);
  header.append_attribute("assetBufferSize") = static_cast<unsigned long long>(h.asset_buffer_size);
  header.append_attribute("assetCount") = static_cast<unsigned long long>(h.asset_count);
  root.append_child("Assets");
  return serialise(doc, pretty);
}

}  // namespace mtc::bridge
