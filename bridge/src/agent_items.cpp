// AgentImpl: observations by data item, for adapters (SHDR) that pass each
// item's changes on rather than documents.
#include "agent_impl.hpp"

namespace mtc::bridge::detail {

namespace {

ItemObservation to_item(const DataItemInfo& item, const Observation& o) {
  return ItemObservation{o.sequence, o.time_ns, item.id, o.value,
                         item.category == Category::Condition};
}

}  // namespace

std::vector<ItemObservation> AgentImpl::latest_observations(std::uint64_t& next) const {
  std::shared_lock lock(data_);
  std::vector<ItemObservation> out;
  out.reserve(model_.data_items().size());
  for (const DataItemInfo& item : model_.data_items()) {
    if (const Observation* o = buffer_.latest(item.slot)) out.push_back(to_item(item, *o));
  }
  next = buffer_.next_sequence();
  return out;
}

bool AgentImpl::observations_since(std::uint64_t from, std::size_t max,
                                   std::vector<ItemObservation>& out, std::uint64_t& next) const {
  std::shared_lock lock(data_);
  if (from < buffer_.first_sequence()) return false;
  // slot -> item of the current model (slots outlive model rebuilds).
  std::vector<std::int32_t> item_of(slots_.size(), -1);
  const auto& items = model_.data_items();
  for (std::size_t i = 0; i < items.size(); ++i) {
    item_of[items[i].slot] = static_cast<std::int32_t>(i);
  }
  std::uint64_t seq = from;
  for (std::size_t taken = 0; seq < buffer_.next_sequence() && taken < max; ++seq, ++taken) {
    const Observation* o = buffer_.find(seq);
    if (!o || o->slot >= item_of.size() || item_of[o->slot] < 0) continue;
    out.push_back(to_item(items[static_cast<std::size_t>(item_of[o->slot])], *o));
  }
  next = seq;
  return true;
}

}  // namespace mtc::bridge::detail
