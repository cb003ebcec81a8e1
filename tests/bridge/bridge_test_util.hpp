// Shared fixtures of the bridge tests: the demo cell as DDS announcements
// (same ids as bridge/devices/cell_*.xml), value builders, XPath helpers.
#pragma once

#include <cctype>
#include <cstdint>
#include <pugixml.hpp>
#include <string>
#include <vector>

#include "mtc/bridge/mtconnect_agent.hpp"

namespace mtc::bridge::test {

inline core::ObservedDataItem item(std::string id, std::string type, std::string sub_type = "") {
  core::ObservedDataItem d;
  d.id = std::move(id);
  d.type = std::move(type);
  d.sub_type = std::move(sub_type);
  d.category = "EVENT";
  return d;
}

inline core::ObservedInterface interface(std::string id, core::InterfaceType type,
                                         std::vector<core::ObservedDataItem> items) {
  core::ObservedInterface i;
  i.id = std::move(id);
  i.name = i.id;
  i.type = type;
  i.data_items = std::move(items);
  return i;
}

inline core::ObservedDevice mill() {
  using core::InterfaceType;
  core::ObservedDevice d;
  d.device_uuid = "mill-0001";
  d.name = "mill";
  d.interfaces = {
      interface("mill_mh", InterfaceType::MaterialHandler,
                {item("mill.mh.state", "INTERFACE_STATE"),
                 item("mill.material_load.req", "MATERIAL_LOAD", "REQUEST"),
                 item("mill.material_unload.req", "MATERIAL_UNLOAD", "REQUEST")}),
      interface(
          "mill_door", InterfaceType::Door,
          {item("mill.door.state", "INTERFACE_STATE"), item("mill.door.door_state", "DOOR_STATE"),
           item("mill.open_door.rsp", "OPEN_DOOR", "RESPONSE"),
           item("mill.close_door.rsp", "CLOSE_DOOR", "RESPONSE")}),
      interface("mill_chuck", InterfaceType::Chuck,
                {item("mill.chuck.state", "INTERFACE_STATE"),
                 item("mill.chuck.chuck_state", "CHUCK_STATE"),
                 item("mill.open_chuck.rsp", "OPEN_CHUCK", "RESPONSE"),
                 item("mill.close_chuck.rsp", "CLOSE_CHUCK", "RESPONSE")}),
      interface("mill_bf", InterfaceType::BarFeeder,
                {item("mill.bf.state", "INTERFACE_STATE"),
                 item("mill.material_feed.req", "MATERIAL_FEED", "REQUEST")}),
  };
  return d;
}

inline core::ObservedDevice robot() {
  using core::InterfaceType;
  core::ObservedDevice d;
  d.device_uuid = "robot-0001";
  d.name = "robot";
  d.interfaces = {interface("robot_mh", InterfaceType::MaterialHandler,
                            {item("robot.mh.state", "INTERFACE_STATE"),
                             item("robot.material_load.rsp", "MATERIAL_LOAD", "RESPONSE"),
                             item("robot.material_unload.rsp", "MATERIAL_UNLOAD", "RESPONSE"),
                             item("robot.open_door.req", "OPEN_DOOR", "REQUEST"),
                             item("robot.close_door.req", "CLOSE_DOOR", "REQUEST"),
                             item("robot.open_chuck.req", "OPEN_CHUCK", "REQUEST"),
                             item("robot.close_chuck.req", "CLOSE_CHUCK", "REQUEST")})};
  return d;
}

inline core::ObservedDevice feeder() {
  core::ObservedDevice d;
  d.device_uuid = "feeder-0001";
  d.name = "feeder";
  d.interfaces = {interface("feeder_bf", core::InterfaceType::BarFeeder,
                            {item("feeder.bf.state", "INTERFACE_STATE"),
                             item("feeder.material_feed.rsp", "MATERIAL_FEED", "RESPONSE")})};
  return d;
}

// The demo cell of apps/cell as it announces itself (uuids cell-*, the
// interface and item ids of mtc::dds::topics): the devices of
// bridge/devices/cell_*.xml.
inline std::string cell_item(const std::string& itf, const char* service, const char* role) {
  return itf + "_" + service + "_" + role;
}

inline core::ObservedInterface cell_interface(
    const std::string& id, core::InterfaceType type,
    const std::vector<std::pair<const char*, const char*>>& services,
    const char* state_type = nullptr) {
  std::vector<core::ObservedDataItem> items{item(id + "_interface_state", "INTERFACE_STATE")};
  if (state_type) {
    std::string lower(state_type);
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    items.push_back(item(id + "_" + lower, state_type));
  }
  for (const auto& [service, role] : services) {
    std::string item_type(service);
    for (char& c : item_type) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    items.push_back(item(cell_item(id, service, role), item_type,
                         std::string(role) == "request" ? "REQUEST" : "RESPONSE"));
  }
  return interface(id, type, items);
}

inline core::ObservedDevice cell_machine() {
  using core::InterfaceType;
  core::ObservedDevice d;
  d.device_uuid = "cell-machine";
  d.name = "machine";
  d.interfaces = {
      cell_interface("material_handler", InterfaceType::MaterialHandler,
                     {{"material_load", "request"}, {"material_unload", "request"}}),
      cell_interface("door", InterfaceType::Door,
                     {{"open_door", "response"}, {"close_door", "response"}}, "DOOR_STATE"),
      cell_interface("chuck", InterfaceType::Chuck,
                     {{"open_chuck", "response"}, {"close_chuck", "response"}}, "CHUCK_STATE"),
      cell_interface("bar_feeder", InterfaceType::BarFeeder, {{"material_feed", "request"}})};
  return d;
}

inline core::ObservedDevice cell_robot() {
  using core::InterfaceType;
  core::ObservedDevice d;
  d.device_uuid = "cell-robot";
  d.name = "robot";
  d.interfaces = {cell_interface("material_handler", InterfaceType::MaterialHandler,
                                 {{"material_load", "response"}, {"material_unload", "response"}}),
                  cell_interface("door", InterfaceType::Door,
                                 {{"open_door", "request"}, {"close_door", "request"}}),
                  cell_interface("chuck", InterfaceType::Chuck,
                                 {{"open_chuck", "request"}, {"close_chuck", "request"}})};
  return d;
}

inline core::ObservedDevice cell_feeder() {
  core::ObservedDevice d;
  d.device_uuid = "cell-feeder";
  d.name = "feeder";
  d.interfaces = {cell_interface("bar_feeder", core::InterfaceType::BarFeeder,
                                 {{"material_feed", "response"}})};
  return d;
}

inline core::ObservedValue value(const std::string& uuid, const std::string& id,
                                 core::ObservedState state, std::int64_t time_ns = 0,
                                 bool redelivered = false) {
  core::ObservedValue o;
  o.device_uuid = uuid;
  o.data_item_id = id;
  o.state = state;
  o.source_time_ns = time_ns;
  o.redelivered = redelivered;
  return o;
}

// A parsed response document.
struct Doc {
  pugi::xml_document xml;
  bool ok = false;

  explicit Doc(const std::string& body) {
    ok = static_cast<bool>(xml.load_buffer(body.data(), body.size()));
  }
  std::size_t count(const char* xpath) const { return xml.select_nodes(xpath).size(); }
  std::string text(const char* xpath) const {
    const pugi::xpath_node n = xml.select_node(xpath);
    if (n.attribute() != nullptr) return n.attribute().value();
    return n.node().text().get();
  }
  std::uint64_t number(const char* xpath) const { return std::stoull("0" + text(xpath)); }
};

// The header's creationTime value (XML or JSON), "" when absent.
inline std::string creation_time(const std::string& body) {
  const std::size_t name = body.find("creationTime");
  if (name == std::string::npos) return {};
  const std::size_t open = body.find_first_of("0123456789", name);
  return open == std::string::npos ? std::string() : body.substr(open, 20);
}

// `body` with its creationTime blanked, to compare documents rendered at
// different times.
inline std::string without_creation_time(std::string body) {
  const std::string time = creation_time(body);
  if (!time.empty()) body.replace(body.find(time), time.size(), time.size(), '-');
  return body;
}

inline Response get(Agent& agent, const std::string& target) {
  Routed r = agent.route("GET", target);
  if (!r.response) return Response{0, "", "<stream/>"};
  return *r.response;
}

inline AgentOptions cell_options(SchemaVersion v = SchemaVersion::V1_6, std::size_t buffer = 1024) {
  AgentOptions o;
  o.schema_version = v;
  o.buffer_size = buffer;
  o.instance_id = 42;
  return o;
}

// Agent with the cell announced over "DDS" (no Devices file).
inline std::unique_ptr<MtconnectAgent> announced_cell(SchemaVersion v = SchemaVersion::V1_6,
                                                      std::size_t buffer = 1024) {
  auto agent = make_agent(cell_options(v, buffer));
  agent->add_device(mill());
  agent->add_device(robot());
  agent->add_device(feeder());
  return agent;
}

inline std::string devices_file(const std::string& name) {
  return std::string(MTC_DEVICES_DIR) + "/" + name;
}

}  // namespace mtc::bridge::test
