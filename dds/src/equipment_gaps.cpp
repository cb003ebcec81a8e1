// Equipment: nothing trusted across a gap (issue 10, the process-fault
// matrix). A counterpart restarted under the same uuid is a new participant:
// the values we wrote for its predecessor are stated again for it
// (note_counterpart_value), and the values it wrote for ours are not taken
// as answers. And scenario 6 is symmetric: when our own heartbeats stopped
// long enough for the counterpart to declare us lost, we take it for lost
// as well.
#include <chrono>
#include <string>

#include "equipment_impl.hpp"

namespace mtc::dds {

// A value naming our interface but another participant of our uuid. One
// naming another interface is the pairing rule's (take_counterpart_value
// excludes us).
bool EquipmentImpl::written_for_predecessor(const InterfaceSlot& itf, const ObservedValue& v,
                                            const detail::ParticipantKey& paired) const noexcept {
  if (paired == detail::ParticipantKey{}) return false;
  if (v.paired_device_uuid != options.device_uuid || v.paired_interface_id != itf.config.id) {
    return false;
  }
  if (!participant) return false;
  return paired != self;
}

void EquipmentImpl::check_own_silence() {
  if (!heartbeat_thread) return;
  const auto now = detail::HeartbeatThread::Clock::now();
  own_silence_handled.resize(groups.size());
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const auto taken = heartbeat_thread->take_silence(g, now);
    const auto silence = taken.length;
    const auto& timing = groups[g]->timing;
    // The counterparts' own rule (detail::silent_for_a_lease); once per silence.
    if (silence < timing.lease() - timing.heartbeat / 2) continue;
    if (taken.since == own_silence_handled[g]) continue;
    own_silence_handled[g] = taken.since;
    for (auto& itf : interfaces) {
      if (itf->group != g || itf->link.load() != LinkState::Up) continue;
      link_lost(*itf,
                "our own heartbeats stopped for " +
                    std::to_string(
                        std::chrono::duration_cast<std::chrono::milliseconds>(silence).count()) +
                    " ms (this process was stopped, starved or hung): the counterpart "
                    "has taken us for lost");
    }
  }
}

}  // namespace mtc::dds
