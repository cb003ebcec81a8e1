// Announcing every endpoint of the participant again (reannounce.hpp,
// detail::Publisher::reannounce): the repair for Fast DDS 2.9.1 endpoint
// rediscovery after a one-sided participant drop (docs/multihost.md, "Cable
// pull").
#include "equipment_impl.hpp"

namespace mtc::dds {

void EquipmentImpl::reannounce_due(SteadyClock::time_point now) {
  if (!reannounce.due(now)) return;
  // Every endpoint, or the repair silently fails for the ones left out: the
  // publisher holds every writer (description, interaction, interface,
  // door/chuck, heartbeat), each timing group's tap its readers.
  std::size_t endpoints = 0;
  try {
    endpoints += publisher->reannounce();
    for (auto& g : groups) endpoints += g->tap->reannounce();
  } catch (const Error& e) {
    diagnostic(std::string("endpoint re-announcement failed: ") + e.what());
  }
  bool still_lost = false;
  for (const auto& itf : interfaces) still_lost |= itf->link.load() == LinkState::Lost;
  reannounce.passed(now, still_lost);
  endpoints_reannounced.store(endpoints, std::memory_order_relaxed);
  reannounce_passes.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace mtc::dds
