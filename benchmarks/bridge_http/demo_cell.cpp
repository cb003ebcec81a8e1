#include "demo_cell.hpp"

#include <algorithm>
#include <pugixml.hpp>
#include <stdexcept>

namespace mtc::bridge::bench {
namespace {

// Values a data item of this type cycles through (all valid transitions
// are not needed here, only changes the agent will record).
std::vector<core::ObservedState> values_for(const std::string& type, const std::string& sub_type) {
  using core::InteractionState;
  if (type == "INTERFACE_STATE") {
    return {core::InterfaceState::Enabled, core::InterfaceState::Disabled};
  }
  if (type == "DOOR_STATE") {
    return {core::DoorState::Open, core::DoorState::Unlatched, core::DoorState::Closed};
  }
  if (type == "CHUCK_STATE") {
    return {core::ChuckState::Open, core::ChuckState::Unlatched, core::ChuckState::Closed};
  }
  if (sub_type == "REQUEST") {
    return {InteractionState::Ready, InteractionState::Active, InteractionState::NotReady};
  }
  if (sub_type == "RESPONSE") {
    return {InteractionState::Ready, InteractionState::Active, InteractionState::Complete};
  }
  return {};
}

}  // namespace

DemoCell::DemoCell(const std::string& devices_file, unsigned io_threads,
                   std::size_t direct_stream_writes) {
  AgentOptions options;
  options.devices_file = devices_file;
  agent_ = make_agent(options);

  // Which items to feed: every Part 5 item of the probe document.
  const Routed probe = agent_->route("GET", "/probe");
  if (!probe.response || probe.response->status != 200) {
    throw std::runtime_error("demo cell: /probe failed");
  }
  pugi::xml_document doc;
  doc.load_string(probe.response->body.c_str());
  for (const auto& hit : doc.select_nodes("//*[local-name()='Device']")) {
    const std::string uuid = hit.node().attribute("uuid").value();
    for (const auto& item : hit.node().select_nodes(".//*[local-name()='DataItem']")) {
      auto values = values_for(item.node().attribute("type").value(),
                               item.node().attribute("subType").value());
      if (values.empty()) {
        continue;
      }
      items_.push_back({uuid, item.node().attribute("id").value(), std::move(values)});
    }
  }
  if (items_.empty()) {
    throw std::runtime_error("demo cell: no Part 5 data items in " + devices_file);
  }
  cursor_.assign(items_.size(), 0);
  for (std::size_t i = 0; i < items_.size(); ++i) {
    feed_next(i);
  }

  ServerOptions server;
  server.port = 0;
  server.io_threads = io_threads;
  server.direct_stream_writes = direct_stream_writes;
  server.max_connections = 1024;
  server_ = std::make_unique<HttpServer>(agent_, server);
  server_->start();
}

DemoCell::~DemoCell() {
  server_->stop();
}

void DemoCell::feed_next(std::size_t index) {
  const auto i = index % items_.size();
  const FedItem& item = items_[i];
  core::ObservedValue value;
  value.device_uuid = item.device_uuid;
  value.data_item_id = item.id;
  value.state = item.values[cursor_[i]++ % item.values.size()];
  agent_->add_value(value);
}

LatencySummary summarize(std::vector<std::chrono::nanoseconds> samples) {
  LatencySummary s;
  s.samples = samples.size();
  if (samples.empty()) {
    return s;
  }
  std::sort(samples.begin(), samples.end());
  auto at = [&](double q) {
    const auto index = static_cast<std::size_t>(q * static_cast<double>(samples.size() - 1));
    return static_cast<double>(samples[index].count()) / 1000.0;
  };
  s.p50_us = at(0.50);
  s.p90_us = at(0.90);
  s.p99_us = at(0.99);
  s.max_us = static_cast<double>(samples.back().count()) / 1000.0;
  double total = 0;
  for (const auto& sample : samples) {
    total += static_cast<double>(sample.count());
  }
  s.mean_us = total / static_cast<double>(samples.size()) / 1000.0;
  return s;
}

void print_summary(std::ostream& out, const LatencySummary& s) {
  out << "{\"samples\":" << s.samples << ",\"p50\":" << s.p50_us << ",\"p90\":" << s.p90_us
      << ",\"p99\":" << s.p99_us << ",\"max\":" << s.max_us << ",\"mean\":" << s.mean_us << "}";
}

}  // namespace mtc::bridge::bench
