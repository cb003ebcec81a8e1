#include "mtc/dds/domain_observer.hpp"

#include <algorithm>
#include <future>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <vector>

#include "device_owners.hpp"
#include "executor.hpp"
#include "left_incarnations.hpp"
#include "lookup_keys.hpp"
#include "mtc/dds/error.hpp"
#include "mtc/qos/participant.hpp"
#include "mtc/qos/presets.hpp"
#include "mw/middleware.hpp"
#include "peer_checks.hpp"
#include "peer_groups.hpp"
#include "reannounce.hpp"

namespace mtc::dds {

using detail::Handle;
using detail::TopicKind;

namespace {

// A state or announcement writer: only its departure says anything (their
// liveliness lease is infinite; heartbeats carry liveness).
struct WriterInfo {
  std::string device;
  bool description = false;
  std::set<std::string> items;
};

// The last value of one data item and which incarnation of its device wrote
// it (a restarted device's old values are never handed over again).
struct LastValue {
  ObservedValue value;
  detail::ParticipantKey participant{};
};

using ItemKey = std::pair<std::string, std::string>;  // (device, data item id)

// Whose an instance is: the device, its data item (state instances) or
// timing group (heartbeat instances), and the incarnation that last wrote it.
struct InstanceOwner {
  std::string device;
  std::string item;
  std::uint32_t group = 0;
  detail::ParticipantKey participant{};
};

}  // namespace

struct DomainObserver::Impl {
  DomainObserverOptions options;
  DomainObserverCallbacks callbacks;

  // Dispatch-thread state.
  std::map<Handle, WriterInfo> writers;
  std::map<std::pair<TopicKind, Handle>, InstanceOwner> instances;
  std::map<ItemKey, LastValue, detail::ViewLess> last_values;
  std::set<ItemKey, detail::ViewLess> lost_items;
  std::set<std::string> lost_devices;
  detail::PeerGroups peer_groups;
  detail::PeerChecks peer_checks;
  // Groups already reported lost by silence (a cue or the backstop), so
  // the backstop neither repeats itself nor wakes for them again.
  std::set<detail::PeerGroupKey> silent_groups;
  // The newest incarnation heard of each device: news of an earlier one
  // (restarted under the same uuid; its participant outlives it by up to a
  // participant lease) must not turn the current one's items UNAVAILABLE.
  std::map<std::string, detail::ParticipantKey> incarnation;
  detail::DeviceOwners owners;  // who speaks for each device (no DDS-Security)
  // Incarnations that said they are leaving: what they write later is not news.
  detail::LeftIncarnations left_incarnations;
  // The tap's readers announced again after a loss (reannounce.hpp).
  detail::ReannounceSchedule reannounce;

  mutable std::mutex devices_mutex;
  std::map<std::string, ObservedDevice> devices;

  // Declared last: destroyed first, so no listener outlives what it uses.
  detail::Executor executor;
  std::unique_ptr<mw::Participant> participant;
  std::unique_ptr<mw::Tap> tap;

  bool wanted(const std::string& device) const {
    const auto& f = options.device_filter;
    return f.empty() || std::find(f.begin(), f.end(), device) != f.end();
  }

  // The participant that announced a device speaks for it (see
  // detail::DeviceOwners); anything else is reported once and ignored.
  bool owned_by_writer(const std::string& device, const Handle& writer, detail::Said said) {
    if (owners.check(device, writer, said)) return true;
    if (owners.first_conflict(device, writer, said)) {
      const auto report = detail::ownership_conflict(owners, device, writer, said);
      if (callbacks.on_ownership_conflict) {
        callbacks.on_ownership_conflict(device, report);
      } else {
        std::cerr << "mtc::dds::DomainObserver: " << report << "\n";
      }
    }
    return false;
  }

  void protocol_violation(const std::string& device, const std::string& report) {
    if (callbacks.on_protocol_violation) {
      callbacks.on_protocol_violation(device, report);
    } else {
      std::cerr << "mtc::dds::DomainObserver: " << report << "\n";
    }
  }

  void handle(detail::ValueEvent& e) {
    const auto& v = e.value;
    if (!wanted(v.device_uuid) || left_incarnations.wrote(e.writer)) return;
    if (!owned_by_writer(v.device_uuid, e.writer, detail::Said::Value)) {
      owners.hold(0, e);
      return;
    }
    const auto verdict = peer_checks.check(0, e.writer, v);
    if (verdict.report) protocol_violation(v.device_uuid, *verdict.report);
    if (!verdict.use) return;
    auto& w = writers[e.writer];
    w.device = v.device_uuid;
    w.items.insert(v.data_item_id);
    const auto writer_participant = detail::participant_of(e.writer);
    // Assigned in place and looked up by views: an item seen before costs
    // no allocation here (this runs for every value the bridge mirrors).
    auto& instance = instances[{e.topic, e.instance}];
    instance.device = v.device_uuid;
    instance.item = v.data_item_id;
    instance.group = 0;
    instance.participant = writer_participant;
    peer_groups.on_value(e.writer, e.topic, v);
    incarnation[v.device_uuid] = writer_participant;
    const std::pair<std::string_view, std::string_view> item(v.device_uuid, v.data_item_id);
    auto& last = detail::find_or_add(last_values, item,
                                     [&] { return ItemKey(v.device_uuid, v.data_item_id); });
    last.value = v;
    last.participant = writer_participant;
    if (const auto lost = lost_items.find(item); lost != lost_items.end()) lost_items.erase(lost);
    if (callbacks.on_value) callbacks.on_value(v);
  }

  void handle(detail::DeviceEvent& e) {
    const auto& d = e.device;
    if (!wanted(d.device_uuid) || left_incarnations.wrote(e.writer)) return;
    if (!owned_by_writer(d.device_uuid, e.writer, detail::Said::Announcement)) {
      owners.hold(e);
      return;
    }
    auto& w = writers[e.writer];
    w.device = d.device_uuid;
    w.description = true;
    instances[{TopicKind::DeviceDescription, e.instance}] = {d.device_uuid, "", 0,
                                                             detail::participant_of(e.writer)};
    incarnation[d.device_uuid] = detail::participant_of(e.writer);
    lost_devices.erase(d.device_uuid);
    {
      std::lock_guard<std::mutex> lock(devices_mutex);
      devices[d.device_uuid] = d;
    }
    if (callbacks.on_device) callbacks.on_device(d);
    // What it wrote before it took the device over.
    for (auto& held : owners.take_values(d.device_uuid, e.writer)) handle(held.event);
  }

  // A heartbeat: its group is alive. A group that was lost gets its last
  // known values handed over again, once every change the heartbeat
  // announces has arrived (before that a remembered value may be stale).
  void handle(detail::HeartbeatEvent& e) {
    const auto& h = e.heartbeat;
    if (!wanted(h.device_uuid) || left_incarnations.wrote(e.writer)) return;
    if (!owned_by_writer(h.device_uuid, e.writer, detail::Said::Heartbeat)) return;
    instances[{TopicKind::Heartbeat, e.instance}] = {h.device_uuid, "", h.group,
                                                     detail::participant_of(e.writer)};
    if (detail::says_leaving(h)) {
      left(e);
      return;
    }
    auto& group = peer_groups.on_heartbeat(e.writer, h, e.heard_ns);
    incarnation[h.device_uuid] = detail::participant_of(e.writer);
    const auto key = detail::PeerGroups::key_of(e.writer, h.device_uuid, h.group);
    silent_groups.erase(key);
    const auto repair = std::chrono::nanoseconds(std::chrono::milliseconds(h.lease_ms)).count();
    if (auto report = peer_groups.behind_report(key, e.heard_ns, repair)) {
      std::cerr << "mtc::dds::DomainObserver: " << *report << '\n';
    }
    if (peer_groups.in_step(group)) recovered(key);
    if (callbacks.on_heartbeat) callbacks.on_heartbeat(h);
  }

  // A group's last heartbeat (period 0): the leave of the incarnation that
  // wrote it, every group of it at once (an equipment says it in all its
  // groups together, and what that incarnation writes from now on, its
  // other leaving heartbeats and its disposals included, is dropped). Not
  // kept as a group's newest (its period rules the silence checks); the
  // groups are marked silent so that no check tells the loss again.
  void left(const detail::HeartbeatEvent& e) {
    const auto& h = e.heartbeat;
    const auto key = detail::PeerGroups::key_of(e.writer, h.device_uuid, h.group);
    if (callbacks.on_heartbeat) callbacks.on_heartbeat(h);
    left_incarnations.remember(e.writer);
    std::vector<detail::PeerGroupKey> groups{key};
    peer_groups.for_each([&](const detail::PeerGroupKey& k, const detail::PeerGroup&) {
      if (k.device == key.device && k.participant == key.participant && k.group != key.group) {
        groups.push_back(k);
      }
    });
    for (const auto& k : groups) {
      silent_groups.insert(k);
      group_lost(k);
    }
    // Items of a group it never beat for, and the device, gone with it.
    items_lost(key.device, items_of(key.device, key.participant, std::nullopt));
    if (current(key.device, key.participant)) device_lost(key.device);
  }

  void recovered(const detail::PeerGroupKey& key) {
    if (key.group == 0 && lost_devices.erase(key.device) != 0 && callbacks.on_device) {
      std::optional<ObservedDevice> device;
      {
        std::lock_guard<std::mutex> lock(devices_mutex);
        if (const auto it = devices.find(key.device); it != devices.end()) device = it->second;
      }
      if (device) callbacks.on_device(*device);
    }
    for (auto it = lost_items.lower_bound({key.device, ""});
         it != lost_items.end() && it->first == key.device;) {
      const auto last = last_values.find(*it);
      if (last == last_values.end() || last->second.value.heartbeat_group != key.group ||
          last->second.participant != key.participant) {
        ++it;
        continue;
      }
      it = lost_items.erase(it);
      auto v = last->second.value;
      v.redelivered = true;
      if (callbacks.on_value) callbacks.on_value(v);
    }
  }

  void device_lost(const std::string& device) {
    if (!lost_devices.insert(device).second) return;
    reannounce.lost(detail::Executor::Clock::now());
    if (callbacks.on_device_lost) callbacks.on_device_lost(device);
  }

  void items_lost(const std::string& device, const std::set<std::string>& items) {
    std::vector<std::string> newly;
    for (const auto& item : items) {
      if (lost_items.insert({device, item}).second) newly.push_back(item);
    }
    if (newly.empty()) return;
    reannounce.lost(detail::Executor::Clock::now());
    if (callbacks.on_items_lost) callbacks.on_items_lost(device, newly);
  }

  void reannounce_due(detail::Executor::Clock::time_point now) {
    if (!reannounce.due(now)) return;
    try {
      tap->reannounce();
    } catch (const Error& e) {
      std::cerr << "mtc::dds::DomainObserver: " << e.what() << '\n';
    }
    reannounce.passed(now, !lost_devices.empty() || !lost_items.empty());
  }

  bool current(const std::string& device, const detail::ParticipantKey& writer_participant) const {
    const auto it = incarnation.find(device);
    return it == incarnation.end() || it->second == writer_participant;
  }

  // Items whose last value that incarnation wrote (all: any incarnation).
  std::set<std::string> items_of(const std::string& device,
                                 const std::optional<detail::ParticipantKey>& written_by,
                                 std::optional<std::uint32_t> group) const {
    std::set<std::string> items;
    for (auto it = last_values.lower_bound({device, ""});
         it != last_values.end() && it->first.first == device; ++it) {
      if (written_by && it->second.participant != *written_by) continue;
      if (group && it->second.value.heartbeat_group != *group) continue;
      items.insert(it->first.second);
    }
    return items;
  }

  // Every item a group's heartbeat vouches for; the device itself with its
  // own group (0).
  void group_lost(const detail::PeerGroupKey& key) {
    items_lost(key.device, items_of(key.device, key.participant, key.group));
    if (key.group == 0 && current(key.device, key.participant)) device_lost(key.device);
    // A restarted device's new participant takes over once the old is lost.
    if (auto held = owners.owner_lost(key.device, key.participant)) handle(*held);
  }

  void handle(detail::WriterLivelinessEvent& e) {
    if (e.alive) return;  // heartbeats and values say when it is back
    if (e.unmatched) peer_checks.forget_writer(e.writer);
    if (const auto* key = peer_groups.heartbeat_writer(e.writer)) {
      heartbeat_writer_lost(e, *key);
      return;
    }
    const auto it = writers.find(e.writer);
    if (it == writers.end() || !e.unmatched) return;
    const auto& device = it->second.device;
    const auto writer_participant = detail::participant_of(e.writer);
    std::optional<detail::DeviceEvent> held;  // another's, replayed once this is gone
    if (it->second.description) {
      if (current(device, writer_participant)) device_lost(device);
      held = owners.release_writer(e.writer);
    } else {
      std::set<std::string> items;
      for (const auto& item : items_of(device, writer_participant, std::nullopt)) {
        if (it->second.items.count(item) != 0) items.insert(item);
      }
      items_lost(device, items);
    }
    writers.erase(it);
    if (held) handle(*held);
  }

  // A group's lease and heartbeat period: what its heartbeats announce.
  std::pair<std::chrono::nanoseconds, std::chrono::nanoseconds> timing_of(
      const detail::PeerGroup& group) const {
    using std::chrono::milliseconds;
    const auto& h = group.newest;
    const auto lease = h.lease_ms != 0 ? milliseconds(h.lease_ms) : options.timing.lease();
    return {lease, group.period_or(options.timing.heartbeat)};
  }

  // The silence rule with the device's own lease; false for a group unknown.
  bool silent(const detail::PeerGroupKey& key) const {
    const auto* group = peer_groups.find(key);
    if (group == nullptr) return false;
    const auto [lease, period] = timing_of(*group);
    return detail::silent_for_a_lease(group->last_heartbeat_steady_ns, detail::steady_ns(), lease,
                                      period);
  }

  // A heartbeat writer's lease expired (checked against the silence rule
  // with the device's own lease) or the writer went away (not checked).
  void heartbeat_writer_lost(const detail::WriterLivelinessEvent& e,
                             const detail::PeerGroupKey& key) {
    // A copy, not a reference: `key` lives in the peer_groups entry that
    // forget_writer() below erases.
    const auto copy = key;  // NOLINT(performance-unnecessary-copy-initialization)
    if (!e.unmatched) {
      if (!silent(copy)) return;
      silent_groups.insert(copy);
    } else {
      peer_groups.forget_writer(e.writer);
    }
    group_lost(copy);
  }

  // The backstop behind the liveliness cue (as in the Equipment): a group
  // silent for its lease plus half its period is lost even if Fast DDS never
  // reported its writer's liveliness lost (measured: 3 of 12 cable pulls in
  // CommsLoss.OutageFailsBothSidesAndRecoversToReady, whose items the bridge
  // would have kept AVAILABLE until the participant lease, 2 s).
  static std::chrono::nanoseconds backstop(std::chrono::nanoseconds lease,
                                           std::chrono::nanoseconds period) {
    return lease + period / 2;
  }

  detail::Executor::Clock::time_point next_silence_check() const {
    using Clock = detail::Executor::Clock;
    auto wake = Clock::time_point::max();
    peer_groups.for_each([&](const detail::PeerGroupKey& key, const detail::PeerGroup& group) {
      if (!group.heard() || silent_groups.count(key) != 0) return;
      const auto [lease, period] = timing_of(group);
      const auto due =
          std::chrono::nanoseconds(group.last_heartbeat_steady_ns) + backstop(lease, period);
      wake = std::min(wake, Clock::time_point(std::chrono::duration_cast<Clock::duration>(due)));
    });
    return wake;
  }

  void check_silence() {
    const auto now = detail::steady_ns();
    std::vector<detail::PeerGroupKey> silent;
    peer_groups.for_each([&](const detail::PeerGroupKey& key, const detail::PeerGroup& group) {
      if (!group.heard() || silent_groups.count(key) != 0) return;
      const auto [lease, period] = timing_of(group);
      if (now - group.last_heartbeat_steady_ns >= backstop(lease, period).count()) {
        silent.push_back(key);
      }
    });
    for (const auto& key : silent) {
      silent_groups.insert(key);
      group_lost(key);
    }
  }

  // Disposed (a graceful leave) or no writer left. A disposal by another
  // incarnation than the one that last wrote the instance is an earlier
  // one's last word, late (a Cyclone writer lingers to deliver it after its
  // participant is gone): the instance is its successor's now.
  void handle(detail::InstanceGoneEvent& e) {
    if (left_incarnations.wrote(e.writer)) return;
    const auto it = instances.find({e.topic, e.instance});
    if (it == instances.end()) return;
    const auto owner = it->second;
    if (e.writer != Handle{} && detail::participant_of(e.writer) != owner.participant) return;
    if (e.topic == TopicKind::Heartbeat) {
      const auto now = incarnation.find(owner.device);
      if (now == incarnation.end()) return;
      const detail::PeerGroupKey key{owner.device, owner.group, now->second};
      // Without writers is a cue, as a liveliness expiry (the Equipment's
      // heartbeat_cue_only); a writer that left is reported unmatched.
      if (!e.disposed) {
        if (!silent(key)) return;
        silent_groups.insert(key);
      }
      group_lost(key);
    } else if (e.topic == TopicKind::DeviceDescription) {
      device_lost(owner.device);
      if (auto held = owners.release_device(owner.device)) handle(*held);
    } else {
      items_lost(owner.device, {owner.item});
    }
  }
  // The observer requests no DEADLINE; a miss would be a cue, not a verdict.
  void handle(detail::DeadlineMissedEvent&) {}
  // Reported once per writer and topic (a flood stays one line), never
  // handed on as a value.
  void handle(detail::ProtocolViolationEvent& e) {
    if (!wanted(e.value.device_uuid)) return;
    if (auto report = peer_checks.refused(e)) protocol_violation(e.value.device_uuid, *report);
  }
  static void handle(detail::IncompatibleQosEvent& e) {
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
  if (!options.security_dir.empty()) {
    if (auto problem = qos::check_security_dir(options.security_dir)) {
      throw ConfigError("DomainObserver: " + *problem);
    }
  }
  auto* impl = impl_.get();
  impl->executor.set_inline_steps(options.inline_steps, /*steps_write=*/false);
  impl->executor.start(
      [impl] { return std::min(impl->next_silence_check(), impl->reannounce.next()); },
      [impl](detail::Executor::Clock::time_point now) {
        impl->check_silence();
        impl->reannounce_due(now);
      });
  qos::ParticipantConfig pc;
  pc.name = "mtc-observer";
  pc.transport = options.transport;
  pc.timing = options.timing;
  pc.security_dir = options.security_dir;
  impl->participant = mw::make_participant(options.middleware, options.domain_id, pc);
  detail::TapConfig tc;
  tc.partitions = {"*"};
  tc.timing = options.timing;
  tc.observer = true;
  // Only values may be handled on the middleware's thread (inline steps):
  // statuses come from threads that hold Fast DDS's discovery and timer
  // locks (as in the Equipment's tap_sink).
  impl->tap = impl->participant->tap(tc, [impl](detail::TapEvent&& event) {
    const bool value = std::holds_alternative<detail::ValueEvent>(event);
    auto task = [impl, ev = std::move(event)]() mutable {
      std::visit([impl](auto& e) { impl->handle(e); }, ev);
    };
    if (value) {
      impl->executor.dispatch(std::move(task));
    } else {
      impl->executor.post(std::move(task));
    }
  });
  // Posted: the executor reads the tap from then on.
  impl->executor.post([impl, lease = options.timing.participant_lease] {
    impl->reannounce.arm(detail::Executor::Clock::now(), lease);
  });
}

DomainObserver::~DomainObserver() {
  // No pass may touch the tap once it is going (the executor runs on).
  std::promise<void> disarmed;
  auto done = disarmed.get_future();
  impl_->executor.post([impl = impl_.get(), &disarmed] {
    impl->reannounce = detail::ReannounceSchedule{};
    disarmed.set_value();
  });
  done.wait();
  // Stop DDS first so nothing new is queued, then drain the dispatch thread.
  impl_->tap.reset();
  impl_->participant.reset();
  impl_->executor.stop();
}

Middleware DomainObserver::middleware() const noexcept {
  return impl_->participant->middleware();
}

std::vector<ObservedDevice> DomainObserver::devices() const {
  std::lock_guard<std::mutex> lock(impl_->devices_mutex);
  std::vector<ObservedDevice> out;
  for (const auto& [uuid, d] : impl_->devices) out.push_back(d);
  return out;
}

}  // namespace mtc::dds
