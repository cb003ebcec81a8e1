#include "mtc/dds/domain_observer.hpp"

#include <algorithm>
#include <iostream>
#include <map>
#include <mutex>
#include <set>

#include "domain_tap.hpp"
#include "executor.hpp"
#include "mtc/dds/detail/entities.hpp"
#include "mtc/dds/detail/topics.hpp"
#include "mtc/qos/participant_qos.hpp"
#include "mtc/qos/presets.hpp"

namespace mtc::dds {

namespace topics = detail::topics;
using detail::Handle;
using detail::Participant;
using detail::TopicKind;

namespace {

struct WriterInfo {
  std::string device;
  bool description = false;
  std::set<std::string> items;
  std::int64_t last_ns = 0;  // last reception from this writer
  bool alive = true;         // no loss reported since its last sign of life
};

}  // namespace

struct DomainObserver::Impl {
  DomainObserverOptions options;
  DomainObserverCallbacks callbacks;

  // Dispatch-thread state.
  std::map<Handle, WriterInfo> writers;
  std::map<std::pair<TopicKind, Handle>, std::pair<std::string, std::string>> instances;
  std::set<std::pair<std::string, std::string>> lost_items;
  std::set<std::string> lost_devices;

  mutable std::mutex devices_mutex;
  std::map<std::string, ObservedDevice> devices;

  // Declared last: destroyed first, so no listener outlives what it uses.
  detail::Executor executor;
  std::unique_ptr<Participant> participant;
  std::unique_ptr<detail::TopicSet> topics;
  std::unique_ptr<detail::DomainTap> tap;

  bool wanted(const std::string& device) const {
    const auto& f = options.device_filter;
    return f.empty() || std::find(f.begin(), f.end(), device) != f.end();
  }

  void handle(detail::ValueEvent& e) {
    const auto& v = e.value;
    if (!wanted(v.device_uuid)) return;
    auto& w = writers[e.writer];
    w.device = v.device_uuid;
    w.items.insert(v.data_item_id);
    w.last_ns = v.reception_time_ns;
    w.alive = true;
    instances[{e.topic, e.instance}] = {v.device_uuid, v.data_item_id};
    lost_items.erase({v.device_uuid, v.data_item_id});
    lost_devices.erase(v.device_uuid);  // it is back: its next loss counts
    if (callbacks.on_value) callbacks.on_value(v);
  }

  void handle(detail::DeviceEvent& e) {
    const auto& d = e.device;
    if (!wanted(d.device_uuid)) return;
    auto& w = writers[e.writer];
    w.device = d.device_uuid;
    w.description = true;
    w.last_ns = topics::realtime_ns();
    w.alive = true;
    instances[{TopicKind::DeviceDescription, e.instance}] = {d.device_uuid, ""};
    lost_devices.erase(d.device_uuid);
    {
      std::lock_guard<std::mutex> lock(devices_mutex);
      devices[d.device_uuid] = d;
    }
    if (callbacks.on_device) callbacks.on_device(d);
  }

  void device_lost(const std::string& device) {
    if (lost_devices.insert(device).second && callbacks.on_device_lost) {
      callbacks.on_device_lost(device);
    }
  }

  void items_lost(const std::string& device, const std::set<std::string>& items) {
    std::vector<std::string> newly;
    for (const auto& item : items) {
      if (lost_items.insert({device, item}).second) newly.push_back(item);
    }
    if (!newly.empty() && callbacks.on_items_lost) callbacks.on_items_lost(device, newly);
  }

  void instance_lost(TopicKind topic, const Handle& instance) {
    const auto it = instances.find({topic, instance});
    if (it == instances.end()) return;
    if (topic == TopicKind::DeviceDescription) {
      device_lost(it->second.first);
    } else {
      items_lost(it->second.first, {it->second.second});
    }
  }

  // True while some writer of `device` has shown no loss since its last
  // sign of life.
  bool any_writer_alive(const std::string& device) const {
    return std::any_of(writers.begin(), writers.end(),
                       [&](const auto& w) { return w.second.device == device && w.second.alive; });
  }

  void handle(detail::WriterLivelinessEvent& e) {
    const auto it = writers.find(e.writer);
    if (it == writers.end()) return;
    WriterInfo& w = it->second;
    if (e.alive) {
      // Back (a process resumed after SIGSTOP, a link up again): the losses
      // reported before are over, so the next ones are reported again.
      // Values resume with the next sample.
      w.alive = true;
      lost_devices.erase(w.device);
      for (const auto& item : w.items) lost_items.erase({w.device, item});
      return;
    }
    // An unmatched writer is gone at once; a lease expiry must be due.
    if (!e.unmatched &&
        detail::expiry_is_premature(w.last_ns, topics::realtime_ns(), options.timing)) {
      return;
    }
    w.alive = false;
    if (!w.description) items_lost(w.device, w.items);
    // A device whose announcement writer is lost, or whose every writer is
    // (its announcement writer does not regain liveliness until it writes
    // again), is gone.
    if (w.description || !any_writer_alive(w.device)) device_lost(w.device);
  }
  void handle(detail::InstanceGoneEvent& e) { instance_lost(e.topic, e.instance); }
  void handle(detail::DeadlineMissedEvent& e) { instance_lost(e.topic, e.instance); }
  void handle(detail::IncompatibleQosEvent& e) {
    std::cerr << "mtc::dds::DomainObserver: a writer on " << detail::topic_name(e.topic)
              << " offers QoS incompatible with the observer (policy id " << e.policy
              << "); is its liveliness lease longer than the observer's?\n";
  }
};

DomainObserver::DomainObserver(const DomainObserverOptions& options,
                               DomainObserverCallbacks callbacks)
    : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
  impl_->callbacks = std::move(callbacks);
  try {
    qos::validate(options.timing);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(std::string("DomainObserver: ") + e.what());
  }
  if (options.domain_id < 0 || options.domain_id > qos::kMaxDomainId) {
    throw ConfigError("DomainObserver: domain id " + std::to_string(options.domain_id) +
                      " outside 0.." + std::to_string(qos::kMaxDomainId));
  }
  auto* impl = impl_.get();
  impl->executor.start(nullptr, nullptr);
  qos::ParticipantConfig pc;
  pc.name = "mtc-observer";
  pc.transport = options.transport;
  pc.timing = options.timing;
  impl->participant = std::make_unique<Participant>(options.domain_id, qos::participant_qos(pc));
  impl->topics = std::make_unique<detail::TopicSet>(*impl->participant, options.timing);
  detail::TapConfig tc;
  tc.partitions = {"*"};
  tc.timing = options.timing;
  tc.observer = true;
  impl->tap = std::make_unique<detail::DomainTap>(
      *impl->participant, *impl->topics, tc, [impl](detail::TapEvent&& event) {
        impl->executor.post([impl, ev = std::move(event)]() mutable {
          std::visit([impl](auto& e) { impl->handle(e); }, ev);
        });
      });
}

DomainObserver::~DomainObserver() {
  // Stop DDS first so nothing new is queued, then drain the dispatch thread.
  impl_->tap.reset();
  impl_->topics.reset();
  impl_->participant.reset();
  impl_->executor.stop();
}

std::vector<ObservedDevice> DomainObserver::devices() const {
  std::lock_guard<std::mutex> lock(impl_->devices_mutex);
  std::vector<ObservedDevice> out;
  for (const auto& [uuid, d] : impl_->devices) out.push_back(d);
  return out;
}

}  // namespace mtc::dds
