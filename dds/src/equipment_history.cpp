// Equipment: keeping each state writer's history short although items are
// written on change only.
//
// A KEEP_LAST 1, TRANSIENT_LOCAL writer keeps the newest change of every
// instance. Fast DDS 2.9.1 announces every hole between the oldest and the
// newest change it keeps with GAPs (each periodic RTPS heartbeat while a
// reader has not acknowledged everything), and the writer and every reader
// walk that range one sequence number at a time (docs/endurance.md). An item
// that never changes would pin the oldest end, and the walk would grow with
// the number of changes since start, as the cost of issue 7 did. So an item
// left behind by more than the span limit is written again, unchanged (same
// value, same source time), which moves the oldest end up: the range stays
// within about four times the writer's items (at least 256 changes). Idle
// writers never reach the limit and cost nothing.
#include <algorithm>
#include <limits>

#include "equipment_impl.hpp"

namespace mtc::dds {

using detail::TopicKind;

namespace {

constexpr std::uint64_t kMinSpan = 256;

}  // namespace

// Calls fn(item, rewrite) for every item the writer of (group, topic) owns
// (of an interaction topic: the writer of that service and side);
// rewrite() writes the item again, unchanged.
template <typename Fn>
void EquipmentImpl::for_each_item(std::size_t group, TopicKind topic, std::size_t interaction,
                                  Fn&& fn) {
  for (auto& itf : interfaces) {
    if (itf->group != group) continue;
    switch (topic) {
      case TopicKind::Request:
      case TopicKind::Response: {
        for (auto index : itf->services) {
          auto& slot = *slots[index];
          if (slot.topic != interaction) continue;
          fn(slot.item, [&] { publish_interaction(slot, slot.item.changed_ns); });
        }
        break;
      }
      case TopicKind::InterfaceState:
        fn(itf->state_item, [&] { publish_interface_state(*itf, itf->state_item.changed_ns); });
        break;
      case TopicKind::DoorState:
      case TopicKind::ChuckState:
        detail::for_door_and_chuck([&](auto tag) {
          using State = typename decltype(tag)::type;
          auto& dc = itf->template door_chuck_item<State>();
          if (!dc.published || detail::DoorChuck<State>::kTopic != topic) return;
          fn(dc.item, [&] { publish_door_chuck<State>(*itf, dc.item.changed_ns); });
        });
        break;
      default:
        break;
    }
  }
}

// The writer's oldest item only moves up, and its items only grow in
// number, so after a look at them the span cannot pass the limit before
// change oldest + limit + 1: until then the writes skip the walk, which
// visits every interface of the group (100 walked per write before).
void EquipmentImpl::bound_history(std::size_t group, TopicKind topic, std::size_t interaction,
                                  std::uint64_t newest, std::uint64_t& scan_at) {
  if (bounding_history || newest < scan_at) return;  // the rewrites below come back here
  std::uint64_t oldest = std::numeric_limits<std::uint64_t>::max();
  std::uint64_t items = 0;
  for_each_item(group, topic, interaction, [&](const PublishedItem& item, auto&&) {
    oldest = std::min(oldest, item.seq);
    ++items;
  });
  if (items == 0) return;
  const std::uint64_t limit = std::max(kMinSpan, 4 * items);
  if (newest - oldest <= limit) {
    scan_at = oldest + limit + 1;
    return;
  }
  bounding_history = true;
  struct Guard {
    bool& flag;
    Guard(const Guard&) = delete;
    Guard& operator=(const Guard&) = delete;
    ~Guard() { flag = false; }
  } guard{bounding_history};
  const std::uint64_t keep_from = newest - limit / 2;
  for_each_item(group, topic, interaction, [&](const PublishedItem& item, auto&& rewrite) {
    if (item.seq < keep_from) rewrite();
  });
  scan_at = keep_from + limit + 1;
}

}  // namespace mtc::dds
