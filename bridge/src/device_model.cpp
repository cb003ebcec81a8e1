// Indexing and querying of the device model; building it lives in
// model_from_file.cpp and model_from_announcements.cpp.
#include "mtc/bridge/device_model.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <stdexcept>
#include <unordered_set>

namespace mtc::bridge {

ModelError::ModelError(std::string file, std::size_t line, std::string reason)
    : std::runtime_error(file + ":" + std::to_string(line) + ": " + reason),
      file_(std::move(file)),
      line_(line),
      reason_(std::move(reason)) {}

std::uint32_t SlotRegistry::slot_for(const std::string& device_uuid, const std::string& item_id) {
  auto [it, inserted] = slots_.try_emplace({device_uuid, item_id}, next_);
  if (inserted) ++next_;
  return it->second;
}

std::string element_name_for_type(std::string_view type) {
  std::string out;
  out.reserve(type.size());
  const auto colon = type.find(':');
  if (colon != std::string_view::npos) {
    out.append(type.substr(0, colon + 1));
    type.remove_prefix(colon + 1);
  }
  bool upper = true;
  for (char c : type) {
    if (c == '_') {
      upper = true;
      continue;
    }
    const auto uc = static_cast<unsigned char>(c);
    out.push_back(static_cast<char>(upper ? std::toupper(uc) : std::tolower(uc)));
    upper = false;
  }
  return out;
}

namespace {

// Counts what estimate_path_cost needs, without recursion.
class ShapeCounter : public pugi::xml_tree_walker {
 public:
  explicit ShapeCounter(TreeShape& shape) : shape_(shape) {}
  bool for_each(pugi::xml_node& node) override {
    ++shape_.nodes;
    shape_.height = std::max<std::uint64_t>(shape_.height, static_cast<std::uint64_t>(depth()) + 1);
    count_text(node.name());
    count_text(node.value());
    if (node.type() != pugi::node_element) return true;
    ++shape_.elements;
    ++shape_.element_names[node.name()];
    std::uint64_t children = 0;
    for (pugi::xml_node c = node.first_child(); !c.empty(); c = c.next_sibling()) {
      ++children;
    }
    shape_.max_children = std::max(shape_.max_children, children);
    std::uint64_t attributes = 0;
    for (pugi::xml_attribute a : node.attributes()) {
      ++attributes;
      ++shape_.attribute_names[a.name()];
      count_text(a.name());
      count_text(a.value());
      shape_.max_attribute_bytes =
          std::max<std::uint64_t>(shape_.max_attribute_bytes, std::strlen(a.value()));
    }
    shape_.attributes += attributes;
    shape_.max_attributes = std::max(shape_.max_attributes, attributes);
    return true;
  }

 private:
  void count_text(std::string_view text) { shape_.text_bytes += text.size(); }
  TreeShape& shape_;
};

}  // namespace

DeviceModel::DeviceModel() = default;

void DeviceModel::index(SlotRegistry& slots) {
  shape_ = TreeShape{};  // the document node itself
  ShapeCounter counter(shape_);
  doc_.traverse(counter);
  shape_.max_children = std::max<std::uint64_t>(shape_.max_children, 1);
  devices_.clear();
  components_.clear();
  items_.clear();
  item_by_xml_id_.clear();
  item_by_source_.clear();
  for (pugi::xml_node dev : devices_node().children()) {
    if (dev.type() != pugi::node_element) continue;
    DeviceInfo info;
    info.id = dev.attribute("id").value();
    info.name = dev.attribute("name").value();
    info.uuid = dev.attribute("uuid").value();
    devices_.push_back(std::move(info));
    const std::size_t device = devices_.size() - 1;
    index_component(dev, device, slots);
    for (pugi::xml_node di : dev.child("DataItems").children("DataItem")) {
      if (std::string_view(di.attribute("type").value()) == "AVAILABILITY") {
        const auto it = item_by_xml_id_.find(di.attribute("id").value());
        if (it != item_by_xml_id_.end()) {
          devices_[device].availability_slot = items_[it->second].slot;
        }
        break;
      }
    }
  }
}

void DeviceModel::index_component(pugi::xml_node node, std::size_t device, SlotRegistry& slots) {
  ComponentInfo comp;
  comp.id = node.attribute("id").value();
  comp.name = node.attribute("name").value();
  comp.element = node.name();
  comp.device = device;
  for (pugi::xml_node ref : node.child("References").children("DataItemRef")) {
    comp.data_item_refs.emplace_back(ref.attribute("idRef").value());
  }
  components_.push_back(std::move(comp));
  const std::size_t component = components_.size() - 1;
  const std::string& uuid = devices_[device].uuid;

  for (pugi::xml_node di : node.child("DataItems").children("DataItem")) {
    DataItemInfo item;
    item.id = di.attribute("id").value();
    const auto src = source_of_xml_id_.find(item.id);
    item.source_id = src == source_of_xml_id_.end() ? item.id : src->second;
    item.name = di.attribute("name").value();
    item.type = di.attribute("type").value();
    item.sub_type = di.attribute("subType").value();
    item.element = element_name_for_type(item.type);
    const std::string_view category = di.attribute("category").value();
    item.category = category == "SAMPLE"      ? Category::Sample
                    : category == "CONDITION" ? Category::Condition
                                              : Category::Event;
    item.device = device;
    item.component = component;
    item.slot = slots.slot_for(uuid, item.source_id);
    item_by_xml_id_.emplace(item.id, items_.size());
    item_by_source_.emplace(std::make_pair(uuid, item.source_id), items_.size());
    items_.push_back(std::move(item));
  }
  for (pugi::xml_node child : node.child("Components").children()) {
    if (child.type() == pugi::node_element) index_component(child, device, slots);
  }
}

std::optional<std::size_t> DeviceModel::find_device(std::string_view name_or_uuid) const {
  for (std::size_t i = 0; i < devices_.size(); ++i) {
    if (devices_[i].name == name_or_uuid) return i;
  }
  for (std::size_t i = 0; i < devices_.size(); ++i) {
    if (devices_[i].uuid == name_or_uuid) return i;
  }
  return std::nullopt;
}

std::optional<std::size_t> DeviceModel::find_device_by_uuid(const std::string& uuid) const {
  for (std::size_t i = 0; i < devices_.size(); ++i) {
    if (devices_[i].uuid == uuid) return i;
  }
  return std::nullopt;
}

std::optional<std::size_t> DeviceModel::find_item(const std::string& device_uuid,
                                                  const std::string& source_id) const {
  const auto it = item_by_source_.find({device_uuid, source_id});
  if (it == item_by_source_.end()) return std::nullopt;
  return it->second;
}

std::vector<std::size_t> DeviceModel::all_items(std::optional<std::size_t> device) const {
  std::vector<std::size_t> out;
  out.reserve(items_.size());
  for (std::size_t i = 0; i < items_.size(); ++i) {
    if (!device || items_[i].device == *device) out.push_back(i);
  }
  return out;
}

std::vector<std::size_t> DeviceModel::select(const std::string& xpath,
                                             std::optional<std::size_t> device,
                                             const PathLimits& limits) const {
  // The walk collecting DataItems below visits every node once more.
  PathLimits xpath_limits = limits;
  xpath_limits.max_visits -= static_cast<double>(shape_.nodes);
  const PathCost cost = estimate_path_cost(xpath, shape_, xpath_limits);
  if (!cost.accepted) throw std::invalid_argument(cost.error);
  pugi::xpath_node_set nodes;
  try {
    const pugi::xpath_query query(xpath.c_str());
    nodes = query.evaluate_node_set(doc_);
  } catch (const pugi::xpath_exception& e) {
    throw std::invalid_argument(e.what());
  }
  // Selected elements (an attribute stands for its element), then one walk
  // of the tree collecting the DataItems at or under them: linear in the
  // tree, however many nested elements the path selected.
  std::unordered_set<const void*> selected;
  for (const pugi::xpath_node& n : nodes) {
    const pugi::xml_node node = n.attribute() ? n.parent() : n.node();
    if (node.type() == pugi::node_element) selected.insert(node.internal_object());
  }
  std::vector<std::size_t> out;
  if (selected.empty()) return out;
  std::ptrdiff_t depth = 0;
  std::ptrdiff_t inside = -1;  // depth of the selected element we are under
  for (pugi::xml_node n = doc_.first_child(); !n.empty();) {
    if (inside >= 0 && depth <= inside) inside = -1;
    if (inside < 0 && selected.count(n.internal_object()) != 0) inside = depth;
    if (inside >= 0 && std::string_view(n.name()) == "DataItem") {
      const auto it = item_by_xml_id_.find(n.attribute("id").value());
      if (it != item_by_xml_id_.end() && (!device || items_[it->second].device == *device)) {
        out.push_back(it->second);
      }
    }
    if (!n.first_child().empty()) {
      n = n.first_child();
      ++depth;
      continue;
    }
    while (!n.empty() && n.next_sibling().empty()) {
      n = n.parent();
      --depth;
    }
    if (!n.empty()) n = n.next_sibling();
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace mtc::bridge
