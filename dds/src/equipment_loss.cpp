// Equipment: loss and return of communication (scenario 6), interpreted on
// the executor thread. DDS gives cues (a heartbeat DEADLINE missed, a
// writer's liveliness lost, an instance disposed or left without writers);
// a cue is checked against what was heard of the counterpart before a link
// is taken as lost, and a backstop finds the silence no cue announced.
#include <algorithm>

#include "equipment_impl.hpp"
#include "mtc/dds/detail/topic_names.hpp"

namespace mtc::dds {

using detail::TopicKind;

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
