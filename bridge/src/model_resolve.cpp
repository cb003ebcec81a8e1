// DeviceModel::resolve_item: mapping DDS data items onto a Devices file that
// was written with its own ids (see the header for the rules).
#include <string_view>

#include "mtc/bridge/device_model.hpp"

namespace mtc::bridge {

namespace {

bool is_interface_element(std::string_view element) {
  constexpr std::string_view kSuffix = "Interface";
  return element.size() > kSuffix.size() &&
         element.substr(element.size() - kSuffix.size()) == kSuffix;
}

bool names_interface(const ComponentInfo& c, const std::string& interface_id) {
  if (interface_id.empty()) return false;
  if (c.id == interface_id || c.name == interface_id) return true;
  const std::size_t n = interface_id.size();
  return c.id.size() > n + 1 && c.id.compare(c.id.size() - n, n, interface_id) == 0 &&
         (c.id[c.id.size() - n - 1] == '_' || c.id[c.id.size() - n - 1] == '.');
}

}  // namespace

// (item, the interface component it stands in) for a hint: the device's
// interfaces' own items and the items they reference with DataItemRef.
std::vector<std::pair<std::size_t, std::size_t>> DeviceModel::interface_candidates(
    std::size_t device, const ItemHint& hint) const {
  std::vector<std::pair<std::size_t, std::size_t>> candidates;
  auto fits = [&](std::size_t i) {
    const DataItemInfo& di = items_[i];
    return di.device == device && di.type == hint.type && di.sub_type == hint.sub_type;
  };
  for (std::size_t c = 0; c < components_.size(); ++c) {
    const ComponentInfo& comp = components_[c];
    if (comp.device != device || !is_interface_element(comp.element)) continue;
    if (!hint.interface_element.empty() && comp.element != hint.interface_element) continue;
    for (const std::string& ref : comp.data_item_refs) {
      const auto it = item_by_xml_id_.find(ref);
      if (it != item_by_xml_id_.end() && fits(it->second)) candidates.emplace_back(it->second, c);
    }
  }
  for (std::size_t i = 0; i < items_.size(); ++i) {
    const std::size_t c = items_[i].component;
    if (!fits(i) || !is_interface_element(components_[c].element)) continue;
    if (!hint.interface_element.empty() && components_[c].element != hint.interface_element) {
      continue;
    }
    candidates.emplace_back(i, c);
  }
  return candidates;
}

std::optional<std::size_t> DeviceModel::resolve_item(const std::string& device_uuid,
                                                     const std::string& source_id,
                                                     const ItemHint& hint) {
  if (auto found = find_item(device_uuid, source_id)) return found;
  const auto device = find_device_by_uuid(device_uuid);
  if (!device) return std::nullopt;
  claimed_.resize(items_.size(), false);
  const DeviceInfo& dev = devices_[*device];
  auto remember = [&](std::size_t item) {
    claimed_[item] = true;
    item_by_source_.emplace(std::make_pair(device_uuid, source_id), item);
    return std::optional<std::size_t>(item);
  };
  for (const std::string& prefix : {dev.id, dev.name}) {
    for (const char sep : {'_', '.'}) {
      std::string xml_id = prefix;
      xml_id += sep;
      xml_id += source_id;
      const auto it = item_by_xml_id_.find(xml_id);
      if (it != item_by_xml_id_.end() && items_[it->second].device == *device &&
          !claimed_[it->second]) {
        return remember(it->second);
      }
    }
  }
  if (hint.type.empty()) return std::nullopt;
  auto candidates = interface_candidates(*device, hint);
  // An interface id that names one of the components decides, even when
  // its item was already given away (then there is no match, rather than a
  // wrong one).
  std::vector<std::pair<std::size_t, std::size_t>> named;
  for (const auto& candidate : candidates) {
    if (names_interface(components_[candidate.second], hint.interface_id)) {
      named.push_back(candidate);
    }
  }
  if (!named.empty() || candidates.size() > 1) candidates.swap(named);
  if (candidates.size() != 1 || claimed_[candidates.front().first]) return std::nullopt;
  return remember(candidates.front().first);
}

}  // namespace mtc::bridge
