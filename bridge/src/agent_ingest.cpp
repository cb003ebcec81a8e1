// AgentImpl: construction, ingest from the DDS observer, stream waiting.
#include <algorithm>
#include <chrono>
#include <new>
#include <optional>
#include <stdexcept>

#include "agent_impl.hpp"
#include "mtc/bridge/xml_text.hpp"

namespace mtc::bridge {

namespace detail {

namespace {

constexpr const char* kUnavailable = "UNAVAILABLE";
constexpr std::size_t kMaxPending = 10000;

std::int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// What a document shows for a state: a number outside the vocabulary (a
// peer's protocol violation, reported by the observer) is not a value the
// schemas allow, and guessing a state would be worse than saying none.
std::string observation_text(const core::ObservedState& state) {
  return state.in_vocabulary() ? core::to_string(state) : std::string(kUnavailable);
}

bool same_items(const core::ObservedInterface& a, const core::ObservedInterface& b) {
  if (a.id != b.id || a.name != b.name || a.type != b.type ||
      a.data_items.size() != b.data_items.size()) {
    return false;
  }
  for (std::size_t i = 0; i < a.data_items.size(); ++i) {
    const auto& x = a.data_items[i];
    const auto& y = b.data_items[i];
    if (x.id != y.id || x.name != y.name || x.type != y.type || x.sub_type != y.sub_type ||
        x.category != y.category) {
      return false;
    }
  }
  return true;
}

bool same_device(const core::ObservedDevice& a, const core::ObservedDevice& b) {
  if (a.name != b.name || a.interfaces.size() != b.interfaces.size()) return false;
  for (std::size_t i = 0; i < a.interfaces.size(); ++i) {
    if (!same_items(a.interfaces[i], b.interfaces[i])) return false;
  }
  return true;
}

// Text from DDS peers becomes XML text (device names, uuids, ids): made
// fit once here, so that the model, the slots and every document agree on
// it and a peer's stray byte cannot spoil documents for good.
void make_safe(std::string& text) {
  if (find_unfit_xml_char(text) != std::string::npos) text = make_xml_safe(text);
}

core::ObservedDevice xml_safe(core::ObservedDevice device) {
  make_safe(device.device_uuid);
  make_safe(device.name);
  for (core::ObservedInterface& itf : device.interfaces) {
    make_safe(itf.id);
    make_safe(itf.name);
    for (core::ObservedDataItem& di : itf.data_items) {
      make_safe(di.id);
      make_safe(di.name);
      make_safe(di.type);
      make_safe(di.sub_type);
      make_safe(di.category);
    }
  }
  return device;
}

bool is_fit(const core::ObservedValue& v) {
  return find_unfit_xml_char(v.device_uuid) == std::string::npos &&
         find_unfit_xml_char(v.data_item_id) == std::string::npos &&
         find_unfit_xml_char(v.interface_id) == std::string::npos;
}

// The configured instance id, else the start time in seconds (what the
// reference agent does), so that a restart shows clients a new instance.
std::uint64_t pick_instance_id(const AgentOptions& options) {
  if (options.instance_id != 0) return options.instance_id;
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::seconds>(
                                        std::chrono::system_clock::now().time_since_epoch())
                                        .count());
}

SchemaVersion pick_version(const AgentOptions& options, const DeviceModel& model) {
  if (options.schema_version) return *options.schema_version;
  if (model.file_version()) return *model.file_version();
  return SchemaVersion::V1_6;
}

}  // namespace

AgentImpl::AgentImpl(const AgentOptions& options)
    : options_(options),
      printer_(options.schema_version.value_or(SchemaVersion::V1_6)),
      json_printer_(printer_.version()),
      instance_id_(pick_instance_id(options)),
      max_count_(options.max_count == 0 ? options.buffer_size
                                        : std::min(options.max_count, options.buffer_size)),
      buffer_(options.buffer_size),
      model_change_ns_(now_ns()) {
  routes_ = make_routes();
  if (!options.devices_file.empty()) {
    model_ = DeviceModel::from_file(options.devices_file, slots_, options.devices_limits);
    printer_ = Printer(pick_version(options, model_));
    json_printer_ = JsonPrinter(printer_.version());
    from_file_ = true;
  }
  mark_unobserved_unavailable(model_change_ns_);
  next_sequence_ = buffer_.next_sequence();
}

bool AgentImpl::append_if_changed(std::uint32_t slot, const std::string& value,
                                  std::int64_t time_ns) {
  const Observation* latest = buffer_.latest(slot);
  if (latest && latest->value == value) {
    ++stats_.duplicates;
    return false;
  }
  buffer_.append(slot, value, time_ns);
  ++stats_.observations;
  return true;
}

void AgentImpl::mark_unobserved_unavailable(std::int64_t time_ns) {
  for (const DataItemInfo& item : model_.data_items()) {
    if (!buffer_.latest(item.slot)) {
      buffer_.append(item.slot, kUnavailable, time_ns);
      ++stats_.observations;
    }
  }
}

void AgentImpl::set_available(std::size_t device, std::int64_t time_ns) {
  const auto slot = model_.devices()[device].availability_slot;
  if (!slot) return;
  // Checked here so that a device's steady AVAILABLE is not a "duplicate".
  const Observation* latest = buffer_.latest(*slot);
  if (!latest || latest->value != "AVAILABLE") append_if_changed(*slot, "AVAILABLE", time_ns);
}

void AgentImpl::rebuild_model() {
  model_ = DeviceModel::from_announcements(announced_, printer_.version(), slots_);
  ++generation_;
  ++stats_.model_changes;
  model_change_ns_ = now_ns();
  mark_unobserved_unavailable(model_change_ns_);
  for (auto it = pending_.begin(); it != pending_.end();) {
    if (const auto item = model_.find_item(it->first.first, it->first.second)) {
      const core::ObservedValue& v = it->second;
      const std::int64_t t = v.source_time_ns != 0 ? v.source_time_ns : model_change_ns_;
      append_if_changed(model_.data_items()[*item].slot, observation_text(v.state), t);
      it = pending_.erase(it);
    } else {
      ++it;
    }
  }
}

const std::string& AgentImpl::model_uuid(const std::string& dds_uuid) const {
  const auto it = uuid_aliases_.find(dds_uuid);
  return it == uuid_aliases_.end() ? dds_uuid : it->second;
}

void AgentImpl::resolve_announced(const core::ObservedDevice& device) {
  const std::string& uuid = model_uuid(device.device_uuid);
  for (const core::ObservedInterface& itf : device.interfaces) {
    for (const core::ObservedDataItem& di : itf.data_items) {
      const ItemHint hint{itf.id, std::string(core::element_name(itf.type)), di.type, di.sub_type};
      model_.resolve_item(uuid, di.id, hint);
    }
  }
}

std::optional<std::size_t> AgentImpl::resolve_value(const core::ObservedValue& value) {
  const std::string& uuid = model_uuid(value.device_uuid);
  if (!from_file_) return model_.find_item(uuid, value.data_item_id);
  ItemHint hint;
  hint.interface_id = value.interface_id;
  switch (value.kind()) {
    case core::ItemKind::Interaction:
      if (value.service) hint.type = std::string(core::to_string(*value.service));
      if (value.sub_type) hint.sub_type = std::string(core::to_string(*value.sub_type));
      break;
    case core::ItemKind::InterfaceState:
      hint.type = "INTERFACE_STATE";
      break;
    case core::ItemKind::DoorState:
      hint.type = "DOOR_STATE";
      break;
    case core::ItemKind::ChuckState:
      hint.type = "CHUCK_STATE";
      break;
  }
  for (const core::ObservedDevice& d : announced_) {
    if (d.device_uuid != value.device_uuid) continue;
    for (const core::ObservedInterface& itf : d.interfaces) {
      if (itf.id == value.interface_id) hint.interface_element = core::element_name(itf.type);
    }
  }
  return model_.resolve_item(uuid, value.data_item_id, hint);
}

bool AgentImpl::make_room_for_announcement() {
  if (announced_.size() < options_.max_announced_devices) return true;
  if (departed_.empty()) return false;
  const std::string gone = departed_.front();
  departed_.erase(departed_.begin());
  announced_.erase(std::remove_if(announced_.begin(), announced_.end(),
                                  [&](const auto& d) { return d.device_uuid == gone; }),
                   announced_.end());
  if (!from_file_) rebuild_model();
  return true;
}

std::optional<std::size_t> AgentImpl::file_device_of(const core::ObservedDevice& device,
                                                     std::string& warning) {
  if (auto d = model_.find_device_by_uuid(model_uuid(device.device_uuid))) return d;
  if (device.name.empty()) return std::nullopt;
  // The file names the device but knows another uuid: map by name, unless
  // the device of that name is already spoken for (its own uuid announced,
  // or another announcement mapped onto it): a second claim is a hijack.
  const auto d = model_.find_device(device.name);
  if (!d) return std::nullopt;
  const std::string& file_uuid = model_.devices()[*d].uuid;
  const bool claimed = std::any_of(announced_.begin(), announced_.end(),
                                   [&](const auto& a) { return a.device_uuid == file_uuid; }) ||
                       std::any_of(uuid_aliases_.begin(), uuid_aliases_.end(),
                                   [&](const auto& alias) { return alias.second == file_uuid; });
  if (claimed) {
    warning = "announcement of " + device.device_uuid + " names device " + device.name + " of " +
              options_.devices_file + ", which another announcement holds: ignored";
    return std::nullopt;
  }
  uuid_aliases_[device.device_uuid] = file_uuid;
  return d;
}

void AgentImpl::add_device(const core::ObservedDevice& announced) {
  const core::ObservedDevice device = xml_safe(announced);
  std::size_t before = 0;
  std::size_t after = 0;
  std::string warning;
  {
    std::unique_lock lock(data_);
    before = buffer_.next_sequence();
    departed_.erase(std::remove(departed_.begin(), departed_.end(), device.device_uuid),
                    departed_.end());
    auto find = [&] {
      return std::find_if(announced_.begin(), announced_.end(),
                          [&](const auto& d) { return d.device_uuid == device.device_uuid; });
    };
    auto it = find();
    // Making room erases from announced_: find again after it.
    if (it == announced_.end() && !make_room_for_announcement()) {
      warning = "announcement of " + device.device_uuid +
                " refused: " + std::to_string(options_.max_announced_devices) +
                " devices announced already (MaxAnnouncedDevices)";
    } else {
      it = find();
      const bool changed = it == announced_.end() || !same_device(*it, device);
      if (it == announced_.end()) {
        announced_.push_back(device);
      } else if (changed) {
        *it = device;
      }
      if (changed && !from_file_) rebuild_model();
      auto d = from_file_ ? file_device_of(device, warning)
                          : model_.find_device_by_uuid(device.device_uuid);
      if (d && from_file_ && changed) resolve_announced(device);
      if (d) set_available(*d, now_ns());
    }
    after = buffer_.next_sequence();
  }
  if (!warning.empty() && options_.on_warning) options_.on_warning(warning);
  notify(after - before);
}

void AgentImpl::add_value(const core::ObservedValue& received) {
  if (!is_fit(received)) {
    core::ObservedValue value = received;
    make_safe(value.device_uuid);
    make_safe(value.data_item_id);
    make_safe(value.interface_id);
    add_value(value);
    return;
  }
  const core::ObservedValue& value = received;
  std::size_t appended = 0;
  std::string warning;
  {
    std::unique_lock lock(data_);
    const auto item = resolve_value(value);
    if (!item) {
      ++stats_.unknown_values;
      stats_.last_unknown = value.device_uuid + "/" + value.data_item_id;
      const std::pair<std::string, std::string> key{value.device_uuid, value.data_item_id};
      if (!from_file_ && (pending_.size() < kMaxPending || pending_.count(key) > 0)) {
        pending_[key] = value;  // applied if an announcement brings the item
      }
      if (from_file_ && options_.on_warning && warned_.size() < kMaxPending &&
          warned_.insert(key).second) {
        warning = "DDS values of device '" + value.device_uuid + "' interface '" +
                  value.interface_id + "' item '" + value.data_item_id +
                  "' are dropped: no DataItem of " + options_.devices_file +
                  " maps to them (said once per item)";
      }
    }
    if (!item) {
      lock.unlock();
      if (!warning.empty()) options_.on_warning(warning);
      return;
    }
    const std::uint64_t before = buffer_.next_sequence();
    const std::int64_t t = value.source_time_ns != 0      ? value.source_time_ns
                           : value.reception_time_ns != 0 ? value.reception_time_ns
                                                          : now_ns();
    const DataItemInfo& info = model_.data_items()[*item];
    append_if_changed(info.slot, observation_text(value.state), t);
    // A device that sends values is reachable, announced or not.
    set_available(info.device, t);
    appended = buffer_.next_sequence() - before;
  }
  notify(appended);
}

void AgentImpl::items_lost(const std::string& received_uuid,
                           const std::vector<std::string>& received_ids) {
  std::string device_uuid = received_uuid;
  make_safe(device_uuid);
  std::vector<std::string> ids = received_ids;
  for (std::string& id : ids) make_safe(id);
  std::size_t appended = 0;
  {
    std::unique_lock lock(data_);
    const std::uint64_t before = buffer_.next_sequence();
    const std::int64_t t = now_ns();
    for (const std::string& id : ids) {
      pending_.erase({device_uuid, id});
      if (const auto item = model_.find_item(model_uuid(device_uuid), id)) {
        append_if_changed(model_.data_items()[*item].slot, kUnavailable, t);
      } else {
        ++stats_.unknown_values;
        stats_.last_unknown = device_uuid;
        stats_.last_unknown += '/';
        stats_.last_unknown += id;
      }
    }
    appended = buffer_.next_sequence() - before;
  }
  notify(appended);
}

void AgentImpl::device_lost(const std::string& received_uuid) {
  std::string device_uuid = received_uuid;
  make_safe(device_uuid);
  std::size_t appended = 0;
  {
    std::unique_lock lock(data_);
    const std::uint64_t before = buffer_.next_sequence();
    const bool announced = std::any_of(announced_.begin(), announced_.end(),
                                       [&](const auto& d) { return d.device_uuid == device_uuid; });
    if (announced &&
        std::find(departed_.begin(), departed_.end(), device_uuid) == departed_.end()) {
      departed_.push_back(device_uuid);
    }
    const auto device = model_.find_device_by_uuid(model_uuid(device_uuid));
    if (device) {
      const std::int64_t t = now_ns();
      for (std::size_t i : model_.all_items(*device)) {
        append_if_changed(model_.data_items()[i].slot, kUnavailable, t);
      }
    }
    appended = buffer_.next_sequence() - before;
  }
  notify(appended);
}

void AgentImpl::notify(std::size_t appended) {
  if (appended == 0) return;
  {
    std::shared_lock lock(data_);
    std::lock_guard wait_lock(wait_mutex_);
    next_sequence_ = buffer_.next_sequence();
  }
  wait_cv_.notify_all();
  std::vector<std::function<void()>> callbacks;
  {
    std::lock_guard lock(subscribers_mutex_);
    callbacks.reserve(subscribers_.size());
    for (const auto& [id, fn] : subscribers_) callbacks.push_back(fn);
  }
  for (const auto& fn : callbacks) fn();
}

AgentStats AgentImpl::stats() const {
  AgentStats s;
  {
    std::shared_lock lock(data_);
    s = stats_;
  }
  std::lock_guard lock(cache_mutex_);
  s.stream_parts_rendered = parts_rendered_;
  s.stream_parts_shared = parts_shared_;
  s.shared_part_bytes = part_cache_.bytes;
  return s;
}

std::uint64_t AgentImpl::next_sequence() const noexcept {
  return next_sequence_.load();
}

bool AgentImpl::wait_for(std::uint64_t from, std::chrono::milliseconds timeout) const {
  std::unique_lock lock(wait_mutex_);
  return wait_cv_.wait_for(lock, timeout, [&] { return next_sequence_.load() > from; });
}

std::uint64_t AgentImpl::subscribe(std::function<void()> on_new_data) {
  std::lock_guard lock(subscribers_mutex_);
  const std::uint64_t id = next_subscriber_++;
  subscribers_.emplace(id, std::move(on_new_data));
  return id;
}

void AgentImpl::unsubscribe(std::uint64_t id) {
  std::lock_guard lock(subscribers_mutex_);
  subscribers_.erase(id);
}

}  // namespace detail

std::unique_ptr<MtconnectAgent> make_agent(const AgentOptions& options) {
  if (options.buffer_size < 2 || options.buffer_size > kMaxBufferSize) {
    throw std::invalid_argument("buffer_size must be from 2 to " + std::to_string(kMaxBufferSize) +
                                ", not " + std::to_string(options.buffer_size));
  }
  if (options.default_count == 0) throw std::invalid_argument("default_count must be at least 1");
  if (options.stream_heartbeat.count() <= 0) {
    throw std::invalid_argument("stream_heartbeat must be positive");
  }
  try {
    return std::make_unique<detail::AgentImpl>(options);
  } catch (const std::bad_alloc&) {
    const std::size_t mib = (options.buffer_size * sizeof(Observation)) >> 20;
    throw std::invalid_argument("out of memory building the agent (a buffer of " +
                                std::to_string(options.buffer_size) + " observations needs " +
                                std::to_string(mib) + " MiB and more): lower buffer_size");
  }
}

}  // namespace mtc::bridge
