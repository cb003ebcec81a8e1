// Equipment: what the DDS readers saw, interpreted on the executor thread:
// counterpart discovery and pairing, counterpart values fed to the machines,
// and loss / return of communication (scenario 6).
#include "equipment_impl.hpp"
#include "mtc/dds/detail/topics.hpp"

namespace mtc::dds {

using detail::TopicKind;

void EquipmentImpl::on_event(std::size_t group, detail::TapEvent& event) {
  std::visit(
      [this, group](auto& e) {
        using T = std::decay_t<decltype(e)>;
        if constexpr (std::is_same_v<T, detail::ValueEvent>) {
          on_value(group, e);
        } else if constexpr (std::is_same_v<T, detail::DeviceEvent>) {
          on_device(e);
        } else if constexpr (std::is_same_v<T, detail::InstanceGoneEvent>) {
          on_gone(group, e.topic, e.instance, "disposed or no writers");
        } else if constexpr (std::is_same_v<T, detail::WriterLivelinessEvent>) {
          if (!e.alive && e.unmatched) on_writer_lost(group, e.writer, "writer unmatched", false);
          if (!e.alive && !e.unmatched) {
            on_writer_lost(group, e.writer, "writer liveliness lost", true);
          }
        } else if constexpr (std::is_same_v<T, detail::DeadlineMissedEvent>) {
          on_deadline_missed(group);
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
  {
    std::lock_guard<std::mutex> lock(binding_mutex);
    itf.cp_uuid = device;
    itf.cp_interface = interface_id;
  }
  set_link(itf, LinkState::Paired, "paired with " + device + "/" + interface_id);
  return true;
}

namespace {

// True when the announced interface carries the opposite side of at least
// one of our services (or we declared none: pairing by type alone).
bool complements(const EquipmentImpl& impl, const InterfaceSlot& itf,
                 const ObservedInterface& other) {
  if (other.type != itf.config.type) return false;
  if (itf.services.empty()) return true;
  for (auto index : itf.services) {
    const auto& s = *impl.slots[index];
    const auto wanted = s.role == core::Role::Requester ? "RESPONSE" : "REQUEST";
    for (const auto& item : other.data_items) {
      if (item.type == core::to_string(s.service) && item.sub_type == wanted) return true;
    }
  }
  return false;
}

}  // namespace

void EquipmentImpl::on_device(detail::DeviceEvent& e) {
  const auto& d = e.device;
  if (d.device_uuid == options.device_uuid) return;
  writer_device[e.writer] = d.device_uuid;
  instance_item[{TopicKind::DeviceDescription, e.instance}] = {d.device_uuid, "", ""};
  writer_last_ns[e.writer] = topics::realtime_ns();
  description_writers.insert(e.writer);
  for (auto& itf : interfaces) {
    if (itf->link.load() != LinkState::Unpaired) continue;
    const auto& spec = itf->config.counterpart;
    if (!spec.device_uuid.empty() && spec.device_uuid != d.device_uuid) continue;
    for (const auto& other : d.interfaces) {
      if (!spec.interface_id.empty() && other.id != spec.interface_id) continue;
      if (complements(*this, *itf, other)) {
        try_bind(*itf, d.device_uuid, other.id);
        break;
      }
    }
  }
}

void EquipmentImpl::on_value(std::size_t group, detail::ValueEvent& e) {
  auto& v = e.value;
  if (v.device_uuid == options.device_uuid) return;
  writer_device[e.writer] = v.device_uuid;
  instance_item[{e.topic, e.instance}] = {v.device_uuid, v.interface_id, v.data_item_id};
  writer_last_ns[e.writer] = v.reception_time_ns;
  writer_interfaces[e.writer].insert(v.interface_id);
  // A change number that skips ahead means this writer changed something we
  // never saw (KEEP_LAST 1 replaced it before delivery, e.g. after a loss).
  auto& last = writer_seq[e.writer];
  // Heartbeats count too: they carry the writer's current change number.
  const bool missed_change = last != 0 && v.sequence_number > last + 1;
  last = std::max(last, v.sequence_number);

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
    if (itf->cp_uuid != v.device_uuid || itf->cp_interface != v.interface_id) continue;
    if (callbacks.on_counterpart_value) {
      guard_callback("on_counterpart_value", [&] { callbacks.on_counterpart_value(v); });
    }
    if (v.state.interface_state() == core::InterfaceState::Unavailable) {
      link_lost(*itf, "counterpart INTERFACE_STATE UNAVAILABLE");
      continue;
    }
    itf->last_heard_ns = v.reception_time_ns;
    if (itf->link.load() != LinkState::Up) link_up(*itf, "value received");
    if (v.kind() != ItemKind::Interaction || !v.service || !v.sub_type) continue;
    const auto role =
        *v.sub_type == core::SubType::Request ? core::Role::Responder : core::Role::Requester;
    if (auto* slot = slot_for(*itf, *v.service, role)) feed_counterpart(*slot, v, missed_change);
  }
}

void EquipmentImpl::feed_counterpart(ServiceSlot& slot, const ObservedValue& v,
                                     bool missed_change) {
  auto& itf = *interfaces[slot.interface_index];
  auto* machine = itf.model->machine(slot.service, slot.role);
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
// loss (detail::expiry_is_premature); say so, since it explains a link that
// stays up.
bool EquipmentImpl::recently_heard(std::size_t group, std::int64_t last_ns,
                                   const std::string& what) {
  const auto now = topics::realtime_ns();
  if (!detail::expiry_is_premature(last_ns, now, groups[group]->timing)) return false;
  diagnostic("ignored " + what + " after only " + std::to_string((now - last_ns) / 1000000) +
             " ms of silence");
  return true;
}

// A DEADLINE miss is a cue to check, not a verdict on the instance it names:
// Fast DDS 2.9 keeps one timer per reader and reports whichever instance owns
// it without re-checking that instance's deadline, an instance that stops
// receiving samples (a departed writer's, one of a device we do not talk to)
// re-fires every period forever, and a peer of another implementation may
// hash keys differently from us (ours: mtc::idl::type_support). What makes a link
// lost is its counterpart interface being silent for about a lease; every
// item of an interface is re-published on each heartbeat, so its freshest
// reception is the measure. Half a heartbeat of slack absorbs the gap
// between the timer and the last reception of the instance that armed it.
void EquipmentImpl::on_deadline_missed(std::size_t group) {
  const auto& timing = groups[group]->timing;
  const auto limit =
      std::chrono::nanoseconds(timing.lease()) - std::chrono::nanoseconds(timing.heartbeat) / 2;
  const auto now = topics::realtime_ns();
  for (auto& itf : interfaces) {
    if (itf->group != group || itf->link.load() != LinkState::Up) continue;
    const auto silence = std::chrono::nanoseconds(now - itf->last_heard_ns);
    if (silence < limit) continue;
    link_lost(*itf, "deadline missed: nothing heard for " +
                        std::to_string(silence.count() / 1000000) + " ms");
  }
}

// Disposal or loss of every writer of an instance: the counterpart said so
// itself, so no silence check applies (DEADLINE misses go through
// on_deadline_missed instead).
void EquipmentImpl::on_gone(std::size_t group, TopicKind topic, const detail::Handle& instance,
                            const char* cause) {
  const auto it = instance_item.find({topic, instance});
  if (it == instance_item.end()) return;
  const auto& owner = it->second;
  for (auto& itf : interfaces) {
    if (itf->cp_uuid != owner.device) continue;
    // A device announcement concerns every interface; items only their group.
    if (topic != TopicKind::DeviceDescription && itf->group != group) continue;
    if (topic == TopicKind::DeviceDescription) {
      link_lost(*itf, std::string("device announcement ") + cause);
    } else if (owner.interface_id == itf->cp_interface) {
      link_lost(*itf, owner.item + ": " + cause);
    }
  }
}

void EquipmentImpl::on_writer_lost(std::size_t group, const detail::Handle& writer,
                                   const char* cause, bool check_silence) {
  const auto it = writer_device.find(writer);
  if (it == writer_device.end()) return;
  if (check_silence &&
      recently_heard(group, writer_last_ns[writer], std::string(cause) + " of " + it->second)) {
    return;
  }
  // The announcement writer stands for the whole device when it goes away;
  // its lease (the equipment's timing) is not used for loss: each interface's
  // items detect that with their own timing. An item writer stands for the
  // interfaces whose items it carried.
  const bool whole_device = description_writers.count(writer) != 0;
  if (whole_device && check_silence) return;
  const auto& fed = writer_interfaces[writer];
  for (auto& itf : interfaces) {
    if (itf->cp_uuid != it->second) continue;
    if (whole_device || fed.count(itf->cp_interface) != 0) link_lost(*itf, cause);
  }
}

void EquipmentImpl::link_lost(InterfaceSlot& itf, const std::string& cause) {
  if (itf.link.load() != LinkState::Up) return;
  set_link(itf, LinkState::Lost, cause);
  handle_batch(itf, itf.model->counterpart_lost(SteadyClock::now()));
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
  ev.current = next;
  ev.cause = cause;
  ev.time_ns = topics::realtime_ns();
  if (next == LinkState::Lost && itf.last_heard_ns != 0) {
    ev.silence = std::chrono::nanoseconds(ev.time_ns - itf.last_heard_ns);
  }
  if (callbacks.on_link) guard_callback("on_link", [&] { callbacks.on_link(ev); });
}

}  // namespace mtc::dds
