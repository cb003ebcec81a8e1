// Equipment: DDS entities, publication of this device's data items (changes
// only), the heartbeat and the DeviceDescription announcement.
#include <algorithm>
#include <chrono>
#include <iostream>
#include <variant>

#include "equipment_impl.hpp"
#include "mtc/dds/detail/topic_names.hpp"
#include "mtc/qos/participant.hpp"
#include "mtc/qos/presets.hpp"

namespace mtc::dds {

using detail::TopicKind;

namespace {

// Readers: the counterparts' partitions when all are known up front,
// otherwise every device's partition (discovery).
std::vector<std::string> reader_partitions(const EquipmentImpl& impl) {
  std::vector<std::string> out;
  for (const auto& itf : impl.interfaces) {
    if (itf->config.counterpart.device_uuid.empty()) return {topics::kAllDevicesPartition};
    out.push_back(topics::device_partition(itf->config.counterpart.device_uuid));
  }
  return out;
}

// Interaction readers: the counterparts' side of each of our services,
// nothing else.
detail::InteractionTopics interaction_topics_read(const EquipmentImpl& impl) {
  detail::InteractionTopics read{};
  for (const auto& s : impl.slots) {
    read[detail::interaction_index(
        s->role == core::Role::Requester ? core::SubType::Response : core::SubType::Request,
        s->service)] = true;
  }
  return read;
}

// The readers of timing group `g`.
detail::TapConfig tap_config(const EquipmentImpl& impl, std::size_t g) {
  detail::TapConfig tc;
  tc.partitions = reader_partitions(impl);
  tc.timing = impl.groups[g]->timing;
  tc.interactions = interaction_topics_read(impl);
  // Announcements are read once, with the equipment's timing.
  tc.topics[static_cast<std::size_t>(detail::TopicKind::DeviceDescription)] = g == 0;
  return tc;
}

// One of our items' values as written: `out` is reused (EquipmentImpl::
// out_value), its strings keep their capacity.
void fill_common(ObservedValue& out, const std::string& device, const std::string& interface_id,
                 std::size_t group, const PublishedItem& item, std::uint64_t seq) {
  out.device_uuid = device;
  out.data_item_id = item.id;
  out.interface_id = interface_id;
  out.service.reset();
  out.sub_type.reset();
  out.sequence_number = seq;
  out.heartbeat_group = static_cast<std::uint32_t>(group);
  out.source_time_ns = item.changed_ns;
  out.paired_device_uuid.clear();
  out.paired_interface_id.clear();
}

// A change bumps the writer's sequence number and stamps the item.
void touch(PublishedItem& item, std::uint64_t& writer_seq, std::int64_t now_ns) {
  item.seq = ++writer_seq;
  item.changed_ns = now_ns;
}

// How long a leaving equipment waits for its peers to acknowledge the
// leave (heartbeats and disposals together): see await_acknowledgments.
constexpr std::chrono::milliseconds kLeaveBound{500};

std::uint32_t to_ms(std::chrono::milliseconds d) {
  return static_cast<std::uint32_t>(d.count());
}

}  // namespace

namespace {

bool same_timing(const qos::Timing& a, const qos::Timing& b) {
  return a.heartbeat == b.heartbeat && a.missed_heartbeats == b.missed_heartbeats &&
         a.reliable_heartbeat == b.reliable_heartbeat;
}

}  // namespace

// Writers of one timing group: only those its interfaces need, one per
// service and side, so that the permissions a device needs are exactly the
// services it requests and provides (however many interfaces use them).
void EquipmentImpl::create_group(std::size_t index) {
  auto& g = *groups[index];
  const auto wq = qos::state_topic(g.timing);
  for (const auto& itf : interfaces) {
    if (itf->group != index) continue;
    for (auto i : itf->services) {
      auto& w = g.interaction[slots[i]->topic];
      if (w.writer) continue;
      w.writer =
          publisher->value_writer(detail::interaction_side(slots[i]->topic), slots[i]->topic, wq);
    }
  }
  g.heartbeat_writer = publisher->heartbeat_writer(qos::heartbeat_topic(g.timing));
  g.interface_writer =
      publisher->value_writer(TopicKind::InterfaceState, detail::kInteractionTopicCount, wq);
  detail::for_door_and_chuck([&](auto tag) {
    using State = typename decltype(tag)::type;
    using Traits = detail::DoorChuck<State>;
    const bool needed = std::any_of(interfaces.begin(), interfaces.end(), [&](const auto& itf) {
      return itf->group == index && itf->template door_chuck_item<State>().published;
    });
    if (needed) {
      g.template door_chuck_writer<State>().writer =
          publisher->value_writer(Traits::kTopic, detail::kInteractionTopicCount, wq);
    }
  });
}

// Groups interfaces by timing; group 0 is the equipment's own.
void EquipmentImpl::group_by_timing() {
  const auto& t = options.timing;
  groups.push_back(std::make_unique<TimingGroup>());
  groups[0]->timing = t;
  for (auto& itf : interfaces) {
    const auto timing = itf->config.timing.value_or(t);
    std::size_t g = 0;
    while (g < groups.size() && !same_timing(groups[g]->timing, timing)) ++g;
    if (g == groups.size()) {
      groups.push_back(std::make_unique<TimingGroup>());
      groups[g]->timing = timing;
    }
    itf->group = g;
  }
}

void EquipmentImpl::create_entities() {
  const auto& t = options.timing;
  qos::ParticipantConfig pc;
  pc.name = "mtc-" + options.device_uuid;
  pc.transport = options.transport;
  pc.faults = options.faults;
  pc.timing = t;
  pc.security_dir = options.security_dir;
  participant = mw::make_participant(options.middleware, options.domain_id, pc);
  self = participant->key();
  publisher = participant->publisher({topics::device_partition(options.device_uuid)});
  group_by_timing();
  for (std::size_t g = 0; g < groups.size(); ++g) create_group(g);
  peer_groups.set_read(interaction_topics_read(*this));
  description_writer = publisher->device_writer(qos::device_description_topic(t));

  // Machines, initial states, announcement; then the executor, the
  // heartbeats and the readers.
  const auto now_ns = topics::realtime_ns();
  for (auto& itf : interfaces) {
    core::MachineOptions defaults;
    defaults.profile = options.profile;
    itf->set_model(std::make_unique<core::InterfaceModel>(itf->config.type, defaults, &itf->hook));
    itf->track_changes(&changed_interfaces, static_cast<std::size_t>(&itf - interfaces.data()));
    for (auto index : itf->services) {
      auto& s = *slots[index];
      core::MachineOptions mo = defaults;
      mo.limits = s.options.limits;
      mo.start_ready = s.options.start_ready;
      mo.counterpart_has_fail = s.options.counterpart_has_fail;
      if (s.role == core::Role::Requester) {
        itf->model_to_change().add_requester(s.service, mo);
      } else {
        itf->model_to_change().add_responder(s.service, mo);
      }
      s.snap_state = itf->model().machine(s.service, s.role)->state();
      publish_interaction(s, now_ns);
    }
    publish_interface_state(*itf, now_ns);
    publish_doors_and_chucks(*itf, now_ns);
  }
  publish_description();

  // Steps on the thread that brings them unless steps_on_executor
  // (defer_reports: see the constructor).
  executor.set_inline_steps(options.inline_steps || !options.steps_on_executor);
  executor.start([this] { return next_wake(); }, [this](SteadyClock::time_point n) { on_wake(n); });
  start_heartbeats();
  // Pairing callbacks run on the executor like every other callback.
  executor.post([this] { bind_configured(); });
  for (std::size_t g = 0; g < groups.size(); ++g) {
    groups[g]->tap = participant->tap(tap_config(*this, g), tap_sink(g));
  }
  // Posted: the executor reads the taps from then on.
  executor.post([this] { reannounce.arm(SteadyClock::now(), options.timing.participant_lease); });
}

// A group's DDS events, handed to the executor. Only values may be stepped
// at once on the middleware's thread (inline steps): statuses (matched,
// liveliness, deadline) come from threads that hold Fast DDS's discovery and
// timer locks, which a write must not wait for.
detail::TapSink EquipmentImpl::tap_sink(std::size_t g) {
  return [this, g](detail::TapEvent&& event) {
    const bool value = std::holds_alternative<detail::ValueEvent>(event);
    auto task = [this, g, ev = std::move(event)]() mutable { on_event(g, ev); };
    if (value) {
      executor.dispatch(std::move(task));
    } else {
      executor.post(std::move(task));
    }
  };
}

// One heartbeat thread for every group; a group's heartbeat is withheld once
// the executor has owed work for a lease: by then the peers' deadline is due
// anyway, and a hung executor must look like what it is.
void EquipmentImpl::start_heartbeats() {
  std::vector<detail::HeartbeatThread::Group> beats;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const auto& t = groups[g]->timing;
    beats.push_back({t.heartbeat, t.lease(), [this, g] { write_heartbeat(g); }});
  }
  heartbeat_thread = std::make_unique<detail::HeartbeatThread>(
      std::move(beats), executor, [this](const std::string& text, bool executor_stuck) {
        // A stuck executor would hold the diagnostic until it recovers, if
        // ever: the operator reads it on stderr now, the application later.
        if (executor_stuck) {
          std::cerr << "mtc::dds::Equipment " + options.device_uuid + ": " + text +
                           " (said at once: the executor cannot)\n"
                    << std::flush;
        }
        executor.post([this, text] { diagnostic(text); });
      });
}

void EquipmentImpl::write_heartbeat(std::size_t index, bool leaving) {
  auto& g = *groups[index];
  const auto changes = [&g](TopicKind t) {
    return g.written[static_cast<std::size_t>(t)].load(std::memory_order_acquire);
  };
  auto& h = g.out_heartbeat;
  h.device_uuid = options.device_uuid;
  h.group = static_cast<std::uint32_t>(index);
  h.period_ms = leaving ? 0 : to_ms(g.timing.heartbeat);
  h.lease_ms = to_ms(g.timing.lease());
  h.beat = ++g.beats;
  h.request_changes = 0;
  h.response_changes = 0;
  h.interaction_changes.clear();
  for (std::size_t i = 0; i < detail::kInteractionTopicCount; ++i) {
    if (!g.interaction[i].writer) continue;  // made before the heartbeats start
    const auto written = g.interaction_written[i].load(std::memory_order_acquire);
    const bool request = detail::interaction_side(i) == TopicKind::Request;
    h.interaction_changes.push_back({detail::interaction_service(i),
                                     request ? core::SubType::Request : core::SubType::Response,
                                     written});
    (request ? h.request_changes : h.response_changes) += written;
  }
  h.interface_state_changes = changes(TopicKind::InterfaceState);
  h.door_state_changes = changes(TopicKind::DoorState);
  h.chuck_state_changes = changes(TopicKind::ChuckState);
  h.source_time_ns = topics::realtime_ns();
  g.heartbeat_writer->write(h);
  heartbeats_written.fetch_add(1, std::memory_order_relaxed);
}

// After the write: a heartbeat announces only changes already written.
void EquipmentImpl::wrote(TimingGroup& g, TopicKind topic, std::uint64_t seq) {
  g.written[static_cast<std::size_t>(topic)].store(seq, std::memory_order_release);
  values_written.fetch_add(1, std::memory_order_relaxed);
}

void EquipmentImpl::wrote_interaction(TimingGroup& g, std::size_t topic, std::uint64_t seq) {
  g.interaction_written[topic].store(seq, std::memory_order_release);
  values_written.fetch_add(1, std::memory_order_relaxed);
}

void EquipmentImpl::shutdown() noexcept {
  // Heartbeats first (peers then see a dead device, not a lying one), then
  // the executor: nothing touches the writers concurrently after.
  if (heartbeat_thread) heartbeat_thread->stop();
  executor.stop();
  if (started) {
    // The leave in data, then the disposals, each acknowledged within one
    // shared bound: KEEP_LAST 1 lets a disposal replace a leaving heartbeat
    // not yet delivered. false: some peer did not answer within the bound
    // (Fast DDS 2.9.1 says ERROR, not TIMEOUT, when a writer's wait runs
    // out); it sees us lost instead, which is what a dead peer needs anyway.
    const auto deadline = SteadyClock::now() + kLeaveBound;
    write_leaving_heartbeats();
    [[maybe_unused]] const bool heard_leaving = await_acknowledgments(deadline);
    dispose_all();
    [[maybe_unused]] const bool left_in_order = await_acknowledgments(deadline);
  }
  for (auto& g : groups) g->tap.reset();
  heartbeat_thread.reset();
  description_writer.reset();
  groups.clear();  // writers before their publisher
  publisher.reset();
  participant.reset();
}

void EquipmentImpl::publish_interaction(ServiceSlot& slot, std::int64_t now_ns) {
  const bool request = slot.role == core::Role::Requester;
  auto& itf = *interfaces[slot.interface_index];
  auto& g = group_of(itf);
  auto& w = g.interaction[slot.topic];
  touch(slot.item, w.seq, now_ns);
  auto& v = out_value;
  fill_common(v, options.device_uuid, itf.config.id, itf.group, slot.item, w.seq);
  v.service = slot.service;
  v.sub_type = request ? core::SubType::Request : core::SubType::Response;
  v.state = itf.model().machine(slot.service, slot.role)->state();
  {
    std::lock_guard<std::mutex> lock(binding_mutex);
    v.paired_device_uuid = itf.cp_uuid;
    v.paired_interface_id = itf.cp_interface;
  }
  detail::ParticipantKey paired{};
  if (itf.cp_group) paired = itf.cp_group->participant;
  w.writer->write(v, paired);
  wrote_interaction(g, slot.topic, w.seq);
  bound_history(itf.group, request ? TopicKind::Request : TopicKind::Response, slot.topic, w.seq,
                w.history_scan_at);
}

void EquipmentImpl::publish_interface_state(InterfaceSlot& itf, std::int64_t now_ns) {
  auto& g = group_of(itf);
  touch(itf.state_item, g.interface_seq, now_ns);
  auto& v = out_value;
  fill_common(v, options.device_uuid, itf.config.id, itf.group, itf.state_item, g.interface_seq);
  v.state = itf.model().interface_state();
  g.interface_writer->write(v, {});
  wrote(g, TopicKind::InterfaceState, g.interface_seq);
  bound_history(itf.group, TopicKind::InterfaceState, detail::kInteractionTopicCount,
                g.interface_seq, g.interface_history_scan_at);
}

template <typename State>
void EquipmentImpl::publish_door_chuck(InterfaceSlot& itf, std::int64_t now_ns) {
  auto& item = itf.door_chuck_item<State>();
  if (!item.published) return;
  auto& g = group_of(itf);
  auto& w = g.door_chuck_writer<State>();
  touch(item.item, w.seq, now_ns);
  auto& v = out_value;
  fill_common(v, options.device_uuid, itf.config.id, itf.group, item.item, w.seq);
  v.state = item.state;
  w.writer->write(v, {});
  wrote(g, detail::DoorChuck<State>::kTopic, w.seq);
  bound_history(itf.group, detail::DoorChuck<State>::kTopic, detail::kInteractionTopicCount, w.seq,
                w.history_scan_at);
}
template void EquipmentImpl::publish_door_chuck<core::DoorState>(InterfaceSlot&, std::int64_t);
template void EquipmentImpl::publish_door_chuck<core::ChuckState>(InterfaceSlot&, std::int64_t);

// Not static: the generic lambda calls a member through `this`, which the
// check does not see in an uninstantiated template body.
// NOLINTNEXTLINE(readability-convert-member-functions-to-static)
void EquipmentImpl::publish_doors_and_chucks(InterfaceSlot& itf, std::int64_t now_ns) {
  detail::for_door_and_chuck(
      [&](auto tag) { publish_door_chuck<typename decltype(tag)::type>(itf, now_ns); });
}

namespace {

ObservedDataItem item(const std::string& id, std::string_view type, std::string_view sub_type) {
  return {id, id, std::string(type), std::string(sub_type), "EVENT"};
}

}  // namespace

// The announcement's bound on data items per interface
// (InterfaceDescription in idl/mtconnect_interfaces.idl): INTERFACE_STATE, a
// door and a chuck state, every service in both roles.
static_assert(1 + 2 + 2 * core::kAllServices.size() <= 32,
              "an interface's data items must fit InterfaceDescription::data_items");

void EquipmentImpl::publish_description() {
  ObservedDevice d;
  d.device_uuid = options.device_uuid;
  d.name = options.device_name;
  for (const auto& itf : interfaces) {
    ObservedInterface i;
    i.id = itf->config.id;
    i.name = itf->config.name;
    i.type = itf->config.type;
    i.data_items.push_back(item(itf->state_item.id, "INTERFACE_STATE", ""));
    detail::for_door_and_chuck([&](auto tag) {
      using State = typename decltype(tag)::type;
      const auto& dc = itf->template door_chuck_item<State>();
      if (dc.published) {
        i.data_items.push_back(item(dc.item.id, detail::DoorChuck<State>::kItemType, ""));
      }
    });
    for (auto index : itf->services) {
      const auto& s = *slots[index];
      i.data_items.push_back(item(s.item.id, core::to_string(s.service),
                                  s.role == core::Role::Requester ? "REQUEST" : "RESPONSE"));
    }
    d.interfaces.push_back(std::move(i));
  }
  description_writer->write(d, ++description_seq, topics::realtime_ns());
}

// The leave said in data (docs/design/middleware-layer.md, section 4): Fast
// DDS 2.9 disposes by the key's MD5 hash alone, which a reader of another
// vendor cannot map to an instance, so each group first writes one last
// heartbeat with period 0, which every reader reads. The heartbeat thread
// is stopped by then: nothing else writes these writers.
void EquipmentImpl::write_leaving_heartbeats() noexcept {
  for (std::size_t g = 0; g < groups.size(); ++g) {
    try {
      write_heartbeat(g, true);
    } catch (const std::exception& e) {
      std::cerr << "mtc::dds::Equipment " << options.device_uuid << ": " << e.what() << '\n';
    }
  }
}

// Graceful leave: disposing every instance (heartbeats included) lets peers
// see our items UNAVAILABLE at once instead of after a lease. Each disposal
// is attempted even if another fails (a destructor must finish).
void EquipmentImpl::dispose_all() noexcept {
  auto attempt = [this](auto&& fn) {
    try {
      fn();
    } catch (const std::exception& e) {
      std::cerr << "mtc::dds::Equipment " << options.device_uuid << ": " << e.what() << '\n';
    }
  };
  const auto& device = options.device_uuid;
  for (auto& itf : interfaces) {
    auto& g = group_of(*itf);
    for (auto index : itf->services) {
      auto& slot = *slots[index];
      attempt([&] { g.interaction[slot.topic].writer->dispose(device, slot.item.id); });
    }
    attempt([&] { g.interface_writer->dispose(device, itf->state_item.id); });
  }
  for (std::size_t g = 0; g < groups.size(); ++g) {
    attempt([&] { groups[g]->heartbeat_writer->dispose(device, static_cast<std::uint32_t>(g)); });
  }
  attempt([&] { description_writer->dispose(device); });
}

// A peer takes our leave from the leaving heartbeats or the disposals, and
// a lost device from our writers going away without them
// (equipment_events.cpp, on_gone and on_writer_lost): the pairing is freed
// only for the first. Deleting the writers right after writing lets a
// peer's discovery report the writers gone before the leave reaches its
// readers (seen as PairingRule.PairingHoldsUntilThePairedDeviceLeaves
// failing about one run in ten), so the leave is waited for, bounded: a peer
// that died keeps its match until its participant lease and never
// acknowledges.
bool EquipmentImpl::await_acknowledgments(SteadyClock::time_point deadline) noexcept {
  if (!publisher) return true;
  const auto left = std::max(deadline - SteadyClock::now(), SteadyClock::duration::zero());
  return publisher->wait_for_acknowledgments(
      std::chrono::duration_cast<std::chrono::nanoseconds>(left));
}

}  // namespace mtc::dds
