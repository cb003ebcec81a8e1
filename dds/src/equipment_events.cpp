// Equipment: what the DDS readers saw, interpreted on the executor thread:
// counterpart discovery and pairing, counterpart values fed to the machines,
// and loss / return of communication (scenario 6). A counterpart interface
// is alive while the heartbeat of its timing group arrives; its values come
// as changes only, so after a loss the last known ones are fed again once
// its heartbeats are back and nothing announced is missing.
#include <algorithm>

#include "equipment_impl.hpp"
#include "mtc/dds/detail/topic_names.hpp"

namespace mtc::dds {

using detail::TopicKind;

void EquipmentImpl::on_event(std::size_t group, detail::TapEvent& event) {
  check_own_silence();
  std::visit(
      [this, group](auto& e) {
        using T = std::decay_t<decltype(e)>;
        if constexpr (std::is_same_v<T, detail::ValueEvent>) {
          on_value(group, e);
        } else if constexpr (std::is_same_v<T, detail::HeartbeatEvent>) {
          on_heartbeat(group, e);
        } else if constexpr (std::is_same_v<T, detail::DeviceEvent>) {
          on_device(e);
        } else if constexpr (std::is_same_v<T, detail::InstanceGoneEvent>) {
          on_gone(group, e.topic, e.instance, e.disposed ? Gone::Disposed : Gone::WithoutWriters,
                  e.writer);
        } else if constexpr (std::is_same_v<T, detail::WriterLivelinessEvent>) {
          if (!e.alive && e.unmatched) {
            peer_checks.forget_writer(e.writer);
            on_writer_lost(group, e.writer, "writer unmatched", false);
          }
          if (!e.alive && !e.unmatched) {
            on_writer_lost(group, e.writer, "writer liveliness lost", true);
          }
        } else if constexpr (std::is_same_v<T, detail::DeadlineMissedEvent>) {
          on_deadline_missed(group);
        } else if constexpr (std::is_same_v<T, detail::ProtocolViolationEvent>) {
          // Never a transition; one report per writer and topic.
          if (auto report = peer_checks.refused(e)) diagnostic(*report);
        } else {
          // Once per topic and group: with several timings, a fast group's
          // readers never match a slow group's writers, by design.
          auto& reported = groups[group]->incompatible_reported[static_cast<std::size_t>(e.topic)];
          if (reported) return;
          reported = true;
          diagnostic(std::string("a peer's writer on ") + detail::topic_name(e.topic) +
                     " offers incompatible QoS (policy id " + e.policy +
                     "); check its heartbeat/lease against ours");
        }
      },
      event);
}

// Without DDS-Security nothing stops a participant from writing another
// device's uuid: the live owner speaks for it (see detail::DeviceOwners).
bool EquipmentImpl::owned_by_writer(const std::string& device, const detail::Handle& writer,
                                    detail::Said said) {
  if (owners.check(device, writer, said)) return true;
  if (owners.first_conflict(device, writer, said)) {
    diagnostic(detail::ownership_conflict(owners, device, writer, said));
  }
  return false;
}

void EquipmentImpl::on_value(std::size_t group, detail::ValueEvent& e) {
  auto& v = e.value;
  if (v.device_uuid == options.device_uuid || from_left_incarnation(e.writer)) return;
  if (!owned_by_writer(v.device_uuid, e.writer, detail::Said::Value)) {
    owners.hold(group, e);
    return;
  }
  const auto verdict = peer_checks.check(group, e.writer, v);
  if (verdict.report) diagnostic(*verdict.report);
  if (!verdict.use) return;
  auto& instance = note_instance(e, v);
  peer_groups.on_value(e.writer, e.topic, v);
  // A change number that skips ahead means this writer changed something we
  // never saw (KEEP_LAST 1 replaced it before delivery, e.g. after a loss).
  // Per timing group: every group's readers see the sample.
  auto& last = writer_seq[{group, e.writer}];
  const bool missed_change = last != 0 && v.sequence_number > last + 1;
  last = std::max(last, v.sequence_number);

  const auto hash = InterfaceSlot::counterpart_hash(v.device_uuid, v.interface_id);
  for (auto& itf : interfaces) {
    // Each timing group's readers feed only that group's interfaces.
    if (itf->group != group) continue;
    // A configured counterpart device with unknown interface id pairs on
    // its first interaction value for one of our services.
    const auto& spec = itf->config.counterpart;
    if (itf->link.load() == LinkState::Unpaired && spec.device_uuid == v.device_uuid &&
        v.kind() == ItemKind::Interaction && v.service && v.sub_type) {
      const auto role =
          *v.sub_type == core::SubType::Request ? core::Role::Responder : core::Role::Requester;
      if (slot_for(*itf, *v.service, role)) try_bind(*itf, v.device_uuid, v.interface_id);
    }
    if (!itf->is_counterpart(v.device_uuid, v.interface_id, hash)) continue;
    // Not an answer to us: the counterpart states its values again for us
    // once it has taken us for its counterpart (note_counterpart_value).
    if (written_for_predecessor(*itf, v, e.paired)) continue;
    take_counterpart_value(*itf, e.writer, v, e.heard_ns, missed_change);
  }
  // After the interfaces: a pairing above replays what was seen before.
  // Found once per instance: a search of every item of 100 interfaces, for
  // every value, was the costliest lookup of this function.
  if (instance.seen == nullptr) {
    instance.seen = &detail::find_or_add(
        seen_values, std::pair<std::string_view, std::string_view>(v.device_uuid, v.data_item_id),
        [&] { return std::pair(v.device_uuid, v.data_item_id); });
  }
  auto& seen = *instance.seen;
  seen.writer = e.writer;
  seen.value = v;
  seen.paired = e.paired;
  seen.heard_ns = e.heard_ns;
}

// Which device, interface and item a value instance is, and which device and
// interfaces its writer speaks for. Nothing of it changes while the same
// writer writes the same item again (the tables only grow), so only the
// first value of an instance, or one from another writer, costs the lookups.
EquipmentImpl::InstanceOwner& EquipmentImpl::note_instance(const detail::ValueEvent& e,
                                                           const ObservedValue& v) {
  auto& owner = instance_item[{e.topic, e.instance}];
  if (owner.writer == e.writer && owner.device == v.device_uuid &&
      owner.interface_id == v.interface_id && owner.item == v.data_item_id) {
    return owner;
  }
  // Assigned in place: a value of an item seen before reuses the strings'
  // storage instead of allocating it again.
  writer_device[e.writer] = v.device_uuid;
  owner.device = v.device_uuid;
  owner.interface_id = v.interface_id;
  owner.item = v.data_item_id;
  owner.group = 0;
  owner.participant = detail::participant_of(e.writer);
  owner.writer = e.writer;
  owner.seen = nullptr;
  writer_interfaces[e.writer].insert(v.interface_id);
  return owner;
}

// Remembers a counterpart value (the last of each item is fed again after a
// loss) and which heartbeat vouches for it. A value of another incarnation
// of the counterpart (restarted under the same uuid) voids what was known,
// and our own values are stated again for it: what we wrote before named its
// predecessor, which it does not take for an answer (scenario 6: it must
// not trust a READY written before we knew of it).
void EquipmentImpl::note_counterpart_value(InterfaceSlot& itf, const detail::Handle& writer,
                                           const ObservedValue& v, std::int64_t heard_ns) {
  const auto writing = detail::participant_of(writer);
  const bool new_incarnation = !itf.cp_group || itf.cp_group->participant != writing;
  // Its predecessor is gone, whether or not its silence was noticed yet (a
  // device that never got its announcement through takes no ownership
  // check): scenario 6, before anything of the new one is taken.
  if (new_incarnation && itf.cp_group) link_lost(itf, "counterpart restarted (a new participant)");
  if (new_incarnation) {
    itf.cp_values.clear();
    itf.cp_stale.clear();
  }
  // In place: no key built (and allocated) for every value.
  if (!itf.cp_group) itf.cp_group.emplace();
  itf.cp_group->device = v.device_uuid;
  itf.cp_group->group = v.heartbeat_group;
  itf.cp_group->participant = writing;
  if (new_incarnation && started) publish_pairing(itf);
  itf.cp_values[v.data_item_id] = v;
  itf.cp_stale.erase(v.data_item_id);
  heard(itf, heard_ns);
}

// Hands one counterpart value to the application and, for an interaction
// item, to the machine of our opposite side.
// The application hears of the value before the transitions it causes (a
// log reads cause, then effect), yet counterpart_state() already shows it
// during that callback: an application that waits for the callback and then
// asks must not see the state from before (the machine's step sets the same
// snapshot again right after).
void EquipmentImpl::deliver(InterfaceSlot& itf, const ObservedValue& v, bool missed_change) {
  ServiceSlot* slot = nullptr;
  if (v.kind() == ItemKind::Interaction && v.service && v.sub_type) {
    const auto role =
        *v.sub_type == core::SubType::Request ? core::Role::Responder : core::Role::Requester;
    slot = slot_for(itf, *v.service, role);
  }
  if (slot != nullptr) {
    if (const auto parsed = v.state.interaction()) slot->snap_counterpart = *parsed;
    slot->addressed =
        v.paired_device_uuid == options.device_uuid && v.paired_interface_id == itf.config.id;
  }
  if (callbacks.on_counterpart_value) {
    report("on_counterpart_value", [this, v] { callbacks.on_counterpart_value(v); });
  }
  if (slot != nullptr) feed_counterpart(*slot, v, missed_change);
}

// A counterpart heartbeat: the link is alive. After a loss it comes back
// with the heartbeat alone (nothing changed while it was gone), and the
// machines get the last known values again, but only once every change
// the heartbeat announces has arrived: until then a cached value may be
// stale, and the change that replaces it is on its way.
void EquipmentImpl::on_heartbeat(std::size_t group, detail::HeartbeatEvent& e) {
  const auto& h = e.heartbeat;
  if (h.device_uuid == options.device_uuid || from_left_incarnation(e.writer)) return;
  if (!owned_by_writer(h.device_uuid, e.writer, detail::Said::Heartbeat)) return;
  instance_item[{TopicKind::Heartbeat, e.instance}] = {h.device_uuid, "", "", h.group,
                                                       detail::participant_of(e.writer)};
  // Its last heartbeat: the disposal that follows may never reach us. Not
  // kept as the group's newest, whose period rules the silence checks.
  if (detail::says_leaving(h)) {
    on_gone(group, TopicKind::Heartbeat, e.instance, Gone::Leaving, e.writer);
    return;
  }
  auto& pg = peer_groups.on_heartbeat(e.writer, h, e.heard_ns);
  const auto key = detail::PeerGroups::key_of(e.writer, h.device_uuid, h.group);
  const auto& timing = groups[group]->timing;
  if (auto report = peer_groups.behind_report(key, e.heard_ns,
                                              std::chrono::nanoseconds(timing.lease()).count())) {
    diagnostic(*report);
  }
  for (auto& itf : interfaces) {
    if (itf->group != group || !itf->cp_group || !(*itf->cp_group == key)) continue;
    heard(*itf, e.heard_ns);
    if (!peer_groups.in_step(pg)) continue;
    // A counterpart that declared its interface UNAVAILABLE stays lost
    // however well it heartbeats.
    const auto state = itf->cp_values.find(topics::interface_state_item_id(itf->cp_interface));
    const bool unavailable =
        state != itf->cp_values.end() &&
        state->second.state.interface_state() == core::InterfaceState::Unavailable;
    if (itf->link.load() == LinkState::Lost && !unavailable) {
      link_up(*itf, "heartbeat resumed");
    }
    if (itf->link.load() == LinkState::Up) redeliver_stale(*itf);
  }
}

// Feeds the machines the counterpart values they have not seen since the
// link was lost (the machines took the loss as UNAVAILABLE).
void EquipmentImpl::redeliver_stale(InterfaceSlot& itf) {
  auto stale = std::move(itf.cp_stale);
  itf.cp_stale.clear();
  for (const auto& id : stale) {
    const auto it = itf.cp_values.find(id);
    if (it == itf.cp_values.end()) continue;
    auto v = it->second;
    v.redelivered = true;
    deliver(itf, v, false);
  }
}

void EquipmentImpl::feed_counterpart(ServiceSlot& slot, const ObservedValue& v,
                                     bool missed_change) {
  auto& itf = *interfaces[slot.interface_index];
  auto* machine = itf.model_to_change().machine(slot.service, slot.role);
  const auto now = SteadyClock::now();
  const auto parsed = v.state.interaction();
  core::StepResult r;
  if (!parsed) {
    // A number outside the vocabulary: the machine reports the violation.
    r = machine->step(core::Event::SeenInvalid, now);
  } else {
    // The responder's ACTIVE was replaced by COMPLETE before it reached us:
    // its change counter proves a change was skipped, so replay ACTIVE
    // rather than calling a correct responder a protocol violator.
    if (missed_change && slot.role == core::Role::Requester &&
        *parsed == core::InteractionState::Complete &&
        machine->state() == core::InteractionState::Active &&
        machine->counterpart() != core::InteractionState::Active) {
      handle_result(slot, machine->on_counterpart(core::InteractionState::Active, now),
                    v.source_time_ns, v.reception_time_ns);
    }
    // We sit in an unacknowledged FAIL and the counterpart shows READY /
    // NOT_READY after a skipped change: it can only have got there through
    // FAIL (e.g. its FAIL was replaced while we were cut off), so replay it.
    const bool idle_value =
        *parsed == core::InteractionState::Ready || *parsed == core::InteractionState::NotReady;
    if (missed_change && idle_value && slot.options.counterpart_has_fail &&
        machine->state() == core::InteractionState::Fail && !machine->fail_acknowledged() &&
        machine->counterpart() != core::InteractionState::Fail) {
      handle_result(slot, machine->on_counterpart(core::InteractionState::Fail, now),
                    v.source_time_ns, v.reception_time_ns);
    }
    r = machine->on_counterpart(*parsed, now);
  }
  handle_result(slot, r, v.source_time_ns, v.reception_time_ns);
  auto_recover(slot, now);
  try_issue(slot, now);
}

// A lease expiry for a writer heard from well within the lease is not a
// loss (detail::silent_for_a_lease); say so, since it explains a link that
// stays up.
bool EquipmentImpl::recently_heard(std::size_t group, std::int64_t last_ns,
                                   const std::string& what) {
  const auto now = detail::steady_ns();
  if (detail::silent_for_a_lease(last_ns, now, groups[group]->timing)) return false;
  diagnostic("ignored " + what + " after only " + std::to_string((now - last_ns) / 1000000) +
             " ms of silence");
  return true;
}

// A heartbeat instance left without writers is a cue like its writer's
// liveliness expiry, and checked the same way: Cyclone ends an expired
// writer's instances so, and after this process was stopped its lease check
// can run before the heartbeats queued meanwhile are read (seen with
// ProcessFaults on Cyclone: a second loss right after the recovery). A writer
// that really left is reported unmatched, and that is not checked.
bool EquipmentImpl::heartbeat_cue_only(const InterfaceSlot& itf, const std::string& device) {
  return recently_heard(itf.group, itf.last_heard_steady_ns,
                        "heartbeat without writers of " + device);
}

// A heartbeat DEADLINE miss is a cue to check, not a verdict on the instance
// it names (see detail::silent_for_a_lease): each Up interface of the group
// is lost when nothing of its counterpart (heartbeat or value) was heard for
// about a lease.
void EquipmentImpl::on_deadline_missed(std::size_t group) {
  const auto now = detail::steady_ns();
  SilentOwners silent;
  for (auto& itf : interfaces) {
    if (itf->group != group || itf->link.load() != LinkState::Up) continue;
    if (!detail::silent_for_a_lease(itf->last_heard_steady_ns, now, groups[group]->timing)) {
      continue;
    }
    link_lost(*itf, "deadline missed: nothing heard for " +
                        std::to_string((now - itf->last_heard_steady_ns) / 1000000) + " ms");
    if (itf->cp_group) silent.emplace_back(group, *itf->cp_group);
  }
  for (const auto& [g, key] : silent) owner_silent(g, key, false);  // see SilentOwners
}

// The backstop behind the DDS cues: an Up interface whose counterpart has
// been silent for a lease plus half a heartbeat (one heartbeat after the cues'
// own rule) is lost even if no cue came. One can stay away for good: an
// interface that went Up on a value before its counterpart's heartbeat
// writer matched has no heartbeat instance whose DEADLINE could be missed
// and no heartbeat writer whose liveliness could lapse, so a cable pull then
// went unnoticed until the participant lease (2 s) unmatched the writers.
namespace {
std::chrono::nanoseconds backstop_silence(const qos::Timing& timing) {
  return timing.lease() + timing.heartbeat / 2;
}
}  // namespace

// A counterpart heard from at heard_ns (steady): its silence counts from
// the newest hearing.
void EquipmentImpl::heard(InterfaceSlot& itf, std::int64_t heard_ns) {
  // The first hearing of an Up interface brings the silence check forward.
  if (itf.last_heard_steady_ns == 0 && heard_ns != 0) silence_check_at.reset();
  itf.last_heard_steady_ns = std::max(itf.last_heard_steady_ns, heard_ns);
}

// Kept between calls, as next_wake asks after every step: only a link going
// Up or a first hearing (both reset it) can bring the answer forward. A
// newer hearing only makes the kept answer early, and the early wake-up
// runs check_silence, which finds nothing and lets it be computed again.
SteadyClock::time_point EquipmentImpl::next_silence_check() const {
  if (silence_check_at) return *silence_check_at;
  auto wake = SteadyClock::time_point::max();
  for (const auto& itf : interfaces) {
    if (itf->link.load() != LinkState::Up || itf->last_heard_steady_ns == 0) continue;
    const auto due = std::chrono::nanoseconds(itf->last_heard_steady_ns) +
                     backstop_silence(groups[itf->group]->timing);
    wake = std::min(
        wake, SteadyClock::time_point(std::chrono::duration_cast<SteadyClock::duration>(due)));
  }
  silence_check_at = wake;
  return wake;
}

void EquipmentImpl::check_silence() {
  silence_check_at.reset();
  const auto now = detail::steady_ns();
  SilentOwners silent;
  for (auto& itf : interfaces) {
    if (itf->link.load() != LinkState::Up || itf->last_heard_steady_ns == 0) continue;
    const auto silence = std::chrono::nanoseconds(now - itf->last_heard_steady_ns);
    if (silence < backstop_silence(groups[itf->group]->timing)) continue;
    link_lost(*itf, "nothing heard for " + std::to_string(silence.count() / 1000000) +
                        " ms (no DDS loss cue came)");
    if (itf->cp_group) silent.emplace_back(itf->group, *itf->cp_group);
  }
  for (const auto& [g, key] : silent) owner_silent(g, key, false);  // see SilentOwners
}

// Disposal, a leaving heartbeat or loss of every writer of an instance: the
// counterpart said so itself, so no silence check applies (DEADLINE misses
// go through on_deadline_missed instead), except to a heartbeat instance
// without writers (heartbeat_cue_only). A heartbeat instance stands for
// every interface its group vouches for. The leave heard twice (heartbeat,
// then disposals) is told once: link_lost and unpairing act on an Up or
// paired interface only.
void EquipmentImpl::on_gone(std::size_t group, TopicKind topic, const detail::Handle& instance,
                            Gone how, const detail::Handle& writer) {
  const char* cause = how == Gone::Disposed  ? "disposed"
                      : how == Gone::Leaving ? "leaving"
                                             : "without writers";
  if (from_left_incarnation(writer)) return;
  const auto it = instance_item.find({topic, instance});
  if (it == instance_item.end()) return;
  // An earlier incarnation's last word, late (a Cyclone writer lingers to
  // deliver its disposals after its participant is gone): the instance is
  // its successor's now.
  if (writer != detail::Handle{} && detail::participant_of(writer) != it->second.participant) {
    return;
  }
  const auto owner = it->second;
  if (how != Gone::WithoutWriters) left_incarnations.remember(writer);
  for (auto& itf : interfaces) {
    if (itf->cp_uuid != owner.device) continue;
    // A device announcement concerns every interface; items only their group.
    if (topic != TopicKind::DeviceDescription && itf->group != group) continue;
    if (topic == TopicKind::DeviceDescription) {
      link_lost(*itf, std::string("device announcement ") + cause);
    } else if (topic == TopicKind::Heartbeat) {
      if (!itf->cp_group || itf->cp_group->group != owner.group) continue;
      if (how == Gone::WithoutWriters && heartbeat_cue_only(*itf, owner.device)) continue;
      link_lost(*itf, std::string("heartbeat ") + cause);
    } else if (owner.interface_id == itf->cp_interface) {
      link_lost(*itf, owner.item + ": " + cause);
    }
  }
  // Only a graceful end disposes or says it is leaving (Equipment's
  // destructor, every instance; the announcement's own disposal may arrive
  // as a loss of its writer).
  if (how == Gone::Leaving) {
    device_left(owner.device,
                "its heartbeat of group " + std::to_string(owner.group) + " said it is leaving");
  } else if (how == Gone::Disposed) {
    device_left(owner.device,
                (owner.item.empty() ? std::string("an instance") : owner.item) + " was disposed");
  }
  if (topic == TopicKind::DeviceDescription) {
    if (auto held = owners.release_device(owner.device)) on_device(*held);
  }
}

void EquipmentImpl::on_writer_lost(std::size_t group, const detail::Handle& writer,
                                   const char* cause, bool check_silence) {
  // Heartbeat writers are remembered after they leave: each timing group's
  // readers report the departure, and a few bytes per restart of a peer
  // are cheap.
  if (const auto* key = peer_groups.heartbeat_writer(writer)) {
    on_heartbeat_writer_lost(group, *key, cause, check_silence);
    return;
  }
  const auto it = writer_device.find(writer);
  if (it == writer_device.end()) return;
  // State and announcement writers assert no liveliness (their lease is
  // infinite): only their departure (unmatched) says anything. The
  // announcement writer stands for the whole device, an item writer for the
  // interfaces whose items it carried.
  // A writer of an earlier incarnation of the counterpart (restarted under
  // the same uuid) says nothing about the current one: its participant
  // outlives it by up to a participant lease.
  if (check_silence) return;
  const bool whole_device = description_writers.count(writer) != 0;
  const auto& fed = writer_interfaces[writer];
  const auto writer_participant = detail::participant_of(writer);
  for (auto& itf : interfaces) {
    if (itf->cp_uuid != it->second) continue;
    if (itf->cp_group && itf->cp_group->participant != writer_participant) continue;
    if (whole_device || fed.count(itf->cp_interface) != 0) link_lost(*itf, cause);
  }
  // Its announcement is gone for good: one another participant made
  // meanwhile is replayed once the links are settled.
  if (whole_device) {
    if (auto held = owners.release_writer(writer)) on_device(*held);
  }
}

// The heartbeat writer of a counterpart group lost its liveliness (checked
// against the silence rule) or went away (not checked).
void EquipmentImpl::on_heartbeat_writer_lost(std::size_t group, const detail::PeerGroupKey& key,
                                             const char* cause, bool check_silence) {
  for (auto& itf : interfaces) {
    if (itf->group != group || !itf->cp_group || !(*itf->cp_group == key)) continue;
    if (itf->link.load() != LinkState::Up) continue;
    if (check_silence && recently_heard(group, itf->last_heard_steady_ns,
                                        std::string(cause) + " of " + key.device)) {
      continue;
    }
    link_lost(*itf, std::string("heartbeat ") + cause);
  }
  owner_silent(group, key, check_silence);  // after the links: a takeover pairs anew
}

// A counterpart's heartbeats stopped for a lease (or its heartbeat writer
// left): its participant no longer owns the device, and an announcement of
// the same uuid by another one (a restart) takes over.
void EquipmentImpl::owner_silent(std::size_t group, const detail::PeerGroupKey& key,
                                 bool check_silence) {
  if (check_silence) {
    const auto* pg = peer_groups.find(key);
    if (pg == nullptr) return;
    using std::chrono::milliseconds;
    const auto& timing = groups[group]->timing;
    const auto& h = pg->newest;
    const auto lease = h.lease_ms != 0 ? milliseconds(h.lease_ms) : timing.lease();
    const auto period = pg->period_or(timing.heartbeat);
    if (!detail::silent_for_a_lease(pg->last_heartbeat_steady_ns, detail::steady_ns(), lease,
                                    period)) {
      return;
    }
  }
  if (auto held = owners.owner_lost(key.device, key.participant)) on_device(*held);
}

void EquipmentImpl::link_lost(InterfaceSlot& itf, const std::string& cause) {
  if (itf.link.load() != LinkState::Up) return;  // an Excluded one has nothing to lose
  // The machines take the loss as UNAVAILABLE: every value is stale now.
  itf.cp_stale.clear();
  for (const auto& [id, value] : itf.cp_values) itf.cp_stale.insert(id);
  set_link(itf, LinkState::Lost, cause);
  reannounce.lost(SteadyClock::now());  // the far side may drop us: see reannounce.hpp
  handle_batch(itf, itf.model_to_change().counterpart_lost(SteadyClock::now()));
}

void EquipmentImpl::link_up(InterfaceSlot& itf, const char* cause) {
  set_link(itf, LinkState::Up, cause);
}

void EquipmentImpl::set_link(InterfaceSlot& itf, LinkState next, const std::string& cause) {
  LinkEvent ev;
  ev.interface_id = itf.config.id;
  {
    std::lock_guard<std::mutex> lock(binding_mutex);
    ev.counterpart_uuid = itf.cp_uuid;
    ev.counterpart_interface_id = itf.cp_interface;
  }
  ev.previous = itf.link.exchange(next);
  if (next == LinkState::Up) silence_check_at.reset();  // see next_silence_check
  ev.current = next;
  ev.cause = cause;
  ev.time_ns = topics::realtime_ns();
  if (next == LinkState::Lost && itf.last_heard_steady_ns != 0) {
    ev.silence = std::chrono::nanoseconds(detail::steady_ns() - itf.last_heard_steady_ns);
  }
  if (callbacks.on_link) report("on_link", [this, ev] { callbacks.on_link(ev); });
}

}  // namespace mtc::dds
