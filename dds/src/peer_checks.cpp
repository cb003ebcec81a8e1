#include "peer_checks.hpp"

#include <limits>

namespace mtc::dds::detail {

namespace {

std::string item_name(const ObservedValue& v) {
  return "device '" + v.device_uuid + "' item '" + v.data_item_id + "'";
}

// Only the sequence of one writer's item says anything: different items of
// one writer share a counter but may be delivered in any order, and a
// sample delivered again after a writer was matched anew repeats its number.
bool went_back(std::uint64_t newest, std::uint64_t received) {
  return newest != 0 && received < newest;
}
bool leapt(std::uint64_t newest, std::uint64_t received) {
  return newest != 0 && received > newest && received - newest > PeerChecks::kLargestPlausibleLeap;
}

}  // namespace

PeerChecks::Verdict PeerChecks::check(std::size_t group, const Handle& writer,
                                      const ObservedValue& value) {
  Verdict verdict;
  const std::string_view item = value.data_item_id;
  auto& reported = find_or_add(reported_, std::pair(writer, item), [&] {
    return ItemKey{writer, value.data_item_id};
  });
  const auto report_once = [&](bool& flag, std::string text) {
    if (flag || verdict.report) return;
    flag = true;
    verdict.report = "protocol violation: " + item_name(value) + " " + std::move(text);
  };
  if (value.kind() == ItemKind::Interaction && (!value.service || !value.sub_type)) {
    verdict.use = false;
    report_once(reported.vocabulary, std::string("carries a ") +
                                         (value.service ? "sub-type" : "service") +
                                         " outside the vocabulary; its values are ignored");
    return verdict;
  }
  if (!value.state.in_vocabulary()) {
    report_once(reported.state,
                "state " + std::to_string(value.state.raw()) + " is outside its vocabulary");
  }
  auto& newest = find_or_add(newest_, std::tuple(writer, group, item), [&] {
    return GroupItemKey{writer, group, value.data_item_id};
  });
  // Text only when there is something to say: this runs for every sample.
  const auto numbers = [&] {
    return " from " + std::to_string(newest) + " to " + std::to_string(value.sequence_number);
  };
  if (went_back(newest, value.sequence_number)) {
    report_once(reported.back, "change number went back" + numbers() +
                                   " (a writer's change numbers only grow); its values are "
                                   "still applied in the order they arrive");
  } else if (leapt(newest, value.sequence_number)) {
    report_once(reported.leap, "change number leapt" + numbers() +
                                   " (more changes than a writer makes between two "
                                   "deliveries); its values are still applied");
  }
  // Follow the writer from here, so one bad number is one report, not a
  // report for every sample after it.
  newest = value.sequence_number;
  return verdict;
}

std::optional<std::string> PeerChecks::refused(const ProtocolViolationEvent& event) {
  if (!refused_.insert({event.writer, event.topic}).second) return std::nullopt;
  return protocol_violation(event);
}

void PeerChecks::forget_writer(const Handle& writer) {
  refused_.erase(refused_.lower_bound({writer, 0}),
                 refused_.lower_bound({writer, std::numeric_limits<std::size_t>::max()}));
  for (auto it = newest_.lower_bound(GroupItemKey{writer, 0, std::string()});
       it != newest_.end() && std::get<0>(it->first) == writer;) {
    it = newest_.erase(it);
  }
  for (auto it = reported_.lower_bound(ItemKey{writer, std::string()});
       it != reported_.end() && it->first.first == writer;) {
    it = reported_.erase(it);
  }
}

}  // namespace mtc::dds::detail
