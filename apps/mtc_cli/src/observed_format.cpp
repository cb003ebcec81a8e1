#include "observed_format.hpp"

namespace mtc::cli {

std::string_view to_string(dds::ItemKind kind) {
  switch (kind) {
    case dds::ItemKind::Interaction:
      return "interaction";
    case dds::ItemKind::InterfaceState:
      return "interface_state";
    case dds::ItemKind::DoorState:
      return "door_state";
    case dds::ItemKind::ChuckState:
      return "chuck_state";
  }
  return "interaction";
}

dds::DomainObserverOptions observer_options(const CommonOptions& common, const ParsedArgs& args) {
  const ObserverSettings s = parse_observer_options(args, common);
  dds::DomainObserverOptions o;
  o.domain_id = common.domain;
  o.device_filter = args.values("device");
  o.transport = s.transport;
  o.middleware = s.middleware;
  o.timing = s.timing;
  o.security_dir = common.security_dir;
  return o;
}

std::string item_label(const dds::ObservedValue& v) {
  switch (v.kind()) {
    case dds::ItemKind::Interaction: {
      std::string label = v.service ? std::string(core::to_string(*v.service)) : v.data_item_id;
      if (v.sub_type) {
        label += " " + std::string(core::to_string(*v.sub_type));
      }
      return label;
    }
    case dds::ItemKind::InterfaceState:
      return "INTERFACE_STATE";
    case dds::ItemKind::DoorState:
      return "DOOR_STATE";
    case dds::ItemKind::ChuckState:
      return "CHUCK_STATE";
  }
  return v.data_item_id;
}

std::string interfaces_json(const dds::ObservedDevice& device) {
  std::string out = "[";
  for (std::size_t i = 0; i < device.interfaces.size(); ++i) {
    const auto& itf = device.interfaces[i];
    std::string items = "[";
    for (std::size_t j = 0; j < itf.data_items.size(); ++j) {
      const auto& di = itf.data_items[j];
      JsonLine item;
      item.field("id", di.id).field("type", di.type).field("sub_type", di.sub_type);
      items += (j > 0 ? "," : "") + item.str();
    }
    items += "]";
    JsonLine line;
    line.field("id", itf.id).field("name", itf.name).field("type", core::to_string(itf.type));
    line.raw_field("data_items", items);
    out += (i > 0 ? "," : "") + line.str();
  }
  return out + "]";
}

std::string interfaces_text(const dds::ObservedDevice& device, std::string_view indent) {
  std::string out;
  for (const auto& itf : device.interfaces) {
    out += std::string(indent) + itf.id + " (" + std::string(core::to_string(itf.type)) + "):";
    const char* sep = " ";
    for (const auto& di : itf.data_items) {
      out += sep + di.type + (di.sub_type.empty() ? "" : " " + di.sub_type);
      sep = ", ";
    }
    out += "\n";
  }
  return out;
}

}  // namespace mtc::cli
