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
  auto& items = items_[writer];
  auto& record = items.try_emplace(value.data_item_id).first->second;
  auto& reported = record.reported;
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
  auto& newest = record.newest_of(group);
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

std::uint64_t& PeerChecks::ItemRecord::newest_of(std::size_t group) {
  for (auto& [g, seq] : newest) {
    if (g == group) return seq;
  }
  return newest.emplace_back(group, 0).second;
}

void PeerChecks::forget_writer(const Handle& writer) {
  refused_.erase(refused_.lower_bound({writer, 0}),
                 refused_.lower_bound({writer, std::numeric_limits<std::size_t>::max()}));
  items_.erase(writer);
}

}  // namespace mtc::dds::detail
