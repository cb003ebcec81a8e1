// Equipment: whom each interface pairs with, and what a counterpart's
// pairing means for us (docs/interaction-model.md, Pairing).
//
// The rule, when no counterpart device is configured: every complementary
// interface announced is a candidate; the election waits `pairing_settle`
// after the first candidate (counterparts started together are then all
// known, whatever order discovery brought them in) and takes the lowest
// (device uuid, interface id). First-come alone would be a coin toss for
// counterparts started together: their announcements race on the network.
// The pairing holds until the paired device leaves (disposes its
// instances); a lost one (killed, hung, cut off) is waited for, so that
// both sides meet again after scenario 6.
//
// Every interaction sample names the writer's pairing, so a counterpart's
// value says at once whether it is meant for us: one naming another
// interface excludes us (LinkState::Excluded), a requester goes ACTIVE only
// once the response names it.
#include <algorithm>

#include "equipment_impl.hpp"
#include "mtc/dds/detail/topic_names.hpp"

namespace mtc::dds {

using detail::TopicKind;

namespace {

// True when the announced interface carries the opposite side of at least
// one of our services (or we declared none: pairing by type alone).
bool complements(const EquipmentImpl& impl, const InterfaceSlot& itf,
                 const ObservedInterface& other) {
  if (other.type != itf.config.type) return false;
  if (itf.services.empty()) return true;
  for (auto index : itf.services) {
    const auto& s = *impl.slots[index];
    const auto* const wanted = s.role == core::Role::Requester ? "RESPONSE" : "REQUEST";
    for (const auto& item : other.data_items) {
      if (item.type == core::to_string(s.service) && item.sub_type == wanted) return true;
    }
  }
  return false;
}

std::string ref(const std::string& device, const std::string& interface_id) {
  return device + "/" + interface_id;
}

}  // namespace

// Before the first samples: a counterpart named in full is their pairing.
void EquipmentImpl::name_configured_counterparts() {
  std::lock_guard<std::mutex> lock(binding_mutex);
  for (auto& itf : interfaces) {
    const auto& spec = itf->config.counterpart;
    if (spec.device_uuid.empty() || spec.interface_id.empty()) continue;
    itf->name_counterpart(spec.device_uuid, spec.interface_id);
  }
}

void EquipmentImpl::bind_configured() {
  for (auto& itf : interfaces) {
    const auto& spec = itf->config.counterpart;
    if (!spec.device_uuid.empty() && !spec.interface_id.empty()) {
      try_bind(*itf, spec.device_uuid, spec.interface_id);
    }
  }
}

bool EquipmentImpl::try_bind(InterfaceSlot& itf, const std::string& device,
                             const std::string& interface_id) {
  if (itf.link.load() != LinkState::Unpaired) return false;
  bool changed = false;
  {
    std::lock_guard<std::mutex> lock(binding_mutex);
    changed = itf.cp_uuid != device || itf.cp_interface != interface_id;
    itf.name_counterpart(device, interface_id);
  }
  itf.elect_at.reset();
  set_link(itf, LinkState::Paired, "paired with " + ref(device, interface_id));
  if (changed) publish_pairing(itf);
  replay_seen_values(itf);
  return true;
}

void EquipmentImpl::publish_pairing(InterfaceSlot& itf) {
  for (auto index : itf.services) {
    auto& slot = *slots[index];
    publish_interaction(slot, slot.item.changed_ns);
  }
}

// The counterpart's values that arrived before the pairing, as if they
// arrived now (INTERFACE_STATE first: it decides whether the link is up).
void EquipmentImpl::replay_seen_values(InterfaceSlot& itf) {
  std::vector<const SeenValue*> known;
  for (auto it = seen_values.lower_bound({itf.cp_uuid, ""});
       it != seen_values.end() && it->first.first == itf.cp_uuid; ++it) {
    if (it->second.value.interface_id == itf.cp_interface) known.push_back(&it->second);
  }
  std::stable_partition(known.begin(), known.end(), [](const SeenValue* s) {
    return s->value.kind() == ItemKind::InterfaceState;
  });
  for (const auto* s : known) {
    if (s->value.state.interface_state() == core::InterfaceState::Unavailable) continue;
    if (written_for_predecessor(itf, s->value, s->paired)) continue;
    take_counterpart_value(itf, s->writer, s->value, s->heard_ns, false);
  }
}

void EquipmentImpl::take_counterpart_value(InterfaceSlot& itf, const detail::Handle& writer,
                                           const ObservedValue& v, std::int64_t heard_ns,
                                           bool missed_change) {
  note_counterpart_value(itf, writer, v, heard_ns);
  // A value replayed after the election was received before it: the
  // heartbeats heard since then say the counterpart is alive now.
  if (const auto* pg = peer_groups.find(*itf.cp_group)) {
    heard(itf, pg->last_heartbeat_steady_ns);
  }
  if (v.state.interface_state() == core::InterfaceState::Unavailable) {
    if (callbacks.on_counterpart_value) {
      report("on_counterpart_value", [this, v] { callbacks.on_counterpart_value(v); });
    }
    link_lost(itf, "counterpart INTERFACE_STATE UNAVAILABLE");
    return;
  }
  if (v.kind() == ItemKind::Interaction) {
    const bool names_another =
        !v.paired_device_uuid.empty() &&
        (v.paired_device_uuid != options.device_uuid || v.paired_interface_id != itf.config.id);
    if (names_another) {
      exclude(itf, v);
      return;
    }
    if (itf.link.load() == LinkState::Excluded) readmit(itf);
  }
  if (itf.link.load() == LinkState::Excluded) {
    deliver(itf, v, missed_change);  // INTERFACE_STATE, DOOR_STATE...: no machine is fed
    return;
  }
  if (itf.link.load() != LinkState::Up) link_up(itf, "value received");
  deliver(itf, v, missed_change);
}

void EquipmentImpl::on_device(detail::DeviceEvent& e) {
  const auto& d = e.device;
  if (d.device_uuid == options.device_uuid) return;
  if (!owned_by_writer(d.device_uuid, e.writer, detail::Said::Announcement)) {
    owners.hold(e);
    return;
  }
  writer_device[e.writer] = d.device_uuid;
  instance_item[{TopicKind::DeviceDescription, e.instance}] = {d.device_uuid, "", "", 0,
                                                               detail::participant_of(e.writer)};
  description_writers.insert(e.writer);
  for (auto& itf : interfaces) {
    const auto& spec = itf->config.counterpart;
    if (!spec.device_uuid.empty() && spec.device_uuid != d.device_uuid) continue;
    for (const auto& other : d.interfaces) {
      if (!spec.interface_id.empty() && other.id != spec.interface_id) continue;
      if (!complements(*this, *itf, other)) continue;
      if (itf->paired_by_rule()) {
        add_candidate(*itf, d.device_uuid, other.id);
      } else {
        try_bind(*itf, d.device_uuid, other.id);
        break;
      }
    }
  }
  // What it wrote before it took the device over.
  for (auto& held : owners.take_values(d.device_uuid, e.writer)) on_value(held.group, held.event);
}

void EquipmentImpl::add_candidate(InterfaceSlot& itf, const std::string& device,
                                  const std::string& interface_id) {
  itf.candidates.emplace(device, interface_id);
  if (itf.link.load() == LinkState::Unpaired && !itf.elect_at) schedule_election(itf);
}

void EquipmentImpl::schedule_election(InterfaceSlot& itf) {
  itf.elect_at = SteadyClock::now() + options.pairing_settle;
  const auto index = itf.index();  // elections come from values: after start
  if (std::find(electing.begin(), electing.end(), index) == electing.end()) {
    electing.push_back(index);
  }
}

SteadyClock::time_point EquipmentImpl::next_election() {
  // Elections are rare (pairing by rule): the list is nearly always empty.
  electing.erase(std::remove_if(electing.begin(), electing.end(),
                                [this](std::size_t index) { return !interfaces[index]->elect_at; }),
                 electing.end());
  auto wake = SteadyClock::time_point::max();
  for (const auto index : electing) wake = std::min(wake, *interfaces[index]->elect_at);
  return wake;
}

void EquipmentImpl::elect_due(SteadyClock::time_point now) {
  for (auto& itf : interfaces) {
    if (!itf->elect_at || now < *itf->elect_at) continue;
    itf->elect_at.reset();
    if (itf->link.load() != LinkState::Unpaired || itf->candidates.empty()) continue;
    // std::set orders by (device uuid, interface id): the lowest comes first.
    const auto winner = *itf->candidates.begin();
    try_bind(*itf, winner.first, winner.second);
  }
}

void EquipmentImpl::device_left(const std::string& device, const std::string& cause) {
  for (auto& itf : interfaces) {
    auto& c = itf->candidates;
    for (auto it = c.lower_bound({device, ""}); it != c.end() && it->first == device;) {
      it = c.erase(it);
    }
    if (itf->paired_by_rule() && itf->cp_uuid == device) {
      unpair(*itf, ref(itf->cp_uuid, itf->cp_interface) + " left (" + cause + ")");
    }
  }
}

void EquipmentImpl::unpair(InterfaceSlot& itf, const std::string& cause) {
  link_lost(itf, cause);
  {
    std::lock_guard<std::mutex> lock(binding_mutex);
    itf.name_counterpart({}, {});
  }
  itf.cp_group.reset();
  itf.cp_values.clear();
  itf.cp_stale.clear();
  itf.last_heard_steady_ns = 0;
  for (auto index : itf.services) slots[index]->addressed = false;
  set_link(itf, LinkState::Unpaired, cause);
  publish_pairing(itf);
  if (!itf.candidates.empty()) schedule_election(itf);
}

// The counterpart serves (or asks) another interface: a request waiting or
// in flight ends as Excluded; an ACTIVE one is withdrawn by a FAIL of our
// own (the counterpart never read it).
void EquipmentImpl::exclude(InterfaceSlot& itf, const ObservedValue& v) {
  if (itf.link.load() != LinkState::Excluded) {
    set_link(itf, LinkState::Excluded,
             ref(v.device_uuid, v.interface_id) + " is paired with " +
                 ref(v.paired_device_uuid, v.paired_interface_id));
  }
  const auto now = SteadyClock::now();
  for (auto index : itf.services) {
    auto& slot = *slots[index];
    slot.addressed = false;
    if (!slot.pending) continue;
    const bool issued = slot.pending->issued;
    end_pending(slot, Outcome::Excluded, core::Reason::None);
    const auto* machine = itf.model().machine(slot.service, slot.role);
    if (issued && machine->state() == core::InteractionState::Active) {
      apply(slot, core::Event::Fail, now);
    }
  }
}

// The counterpart names us (or nobody) again: its values are ours once more.
// What it held while it served another is not fed to our machines (a
// response ACTIVE for another requester would read as a violation): its new
// pairing rewrote every item, and each arrives anew.
void EquipmentImpl::readmit(InterfaceSlot& itf) {
  itf.cp_stale.clear();
  link_up(itf, "no longer paired with another");
}

}  // namespace mtc::dds
