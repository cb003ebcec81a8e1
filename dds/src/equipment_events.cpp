// Equipment: what the DDS readers saw, interpreted on the executor thread:
// counterpart discovery and pairing, counterpart values fed to the machines,
// and heartbeats (loss of communication: equipment_loss.cpp). A counterpart
// interface is alive while the heartbeat of its timing group arrives; its
// values come as changes only, so after a loss the last known ones are fed
// again once its heartbeats are back and nothing announced is missing.
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

}  // namespace mtc::dds
