// What the runtime does with a decoded value before any machine or agent
// sees it (dds/src/domain_tap.cpp, equipment_events.cpp, domain_observer.cpp):
// the tap's topic rule for interaction values, then the peer checks
// (detail::PeerChecks). Used by fuzz_dds_samples, which checks every verdict
// against the rules as dds/src/peer_checks.hpp states them: a value is
// dropped only when it names no service or sub-type, and each broken rule is
// reported once per writer and item (once per writer and topic for a
// refused value), the first unreported one when several break at once.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <utility>

#include "fuzz_support.hpp"
#include "mtc/dds/detail/sample_decoding.hpp"
#include "peer_checks.hpp"

namespace mtc::fuzz {

class ReceivePath {
 public:
  static constexpr std::uint8_t kWriters = 4;
  static constexpr std::size_t kGroups = 3;

  // A value as a reader of `group` receives it from writer `writer` on
  // interaction topic `topic` (ignored for other items); true when the
  // runtime goes on with it (the machines, the bridge's agent).
  bool receive(std::uint8_t writer, std::size_t group, std::size_t topic,
               const core::ObservedValue& value) {
    const auto handle = handle_of(writer);
    if (value.kind() == core::ItemKind::Interaction &&
        !dds::detail::on_its_interaction_topic(value, topic)) {
      const auto report =
          checks_.refused(dds::detail::ProtocolViolationEvent{topic, handle, value});
      const bool first = refused_.insert({writer, topic}).second;
      require(report.has_value() == first, "a refused value reported other than once per topic");
      require(!report || !report->empty(), "an empty report of a refused value");
      return false;
    }
    const auto verdict = checks_.check(group, handle, value);
    const bool expected_report = expect(writer, group, value);
    const bool expected_use = !names_no_service(value);
    require(verdict.use == expected_use, "a value dropped or kept against the rules");
    require(verdict.report.has_value() == expected_report,
            "a broken rule reported other than once per writer and item");
    require(!verdict.report || verdict.report->rfind("protocol violation: ", 0) == 0,
            "a report that does not say what it is");
    return verdict.use;
  }

  // The writer left: what is known of it goes, so it may be reported anew.
  void forget(std::uint8_t writer) {
    checks_.forget_writer(handle_of(writer));
    for (auto it = newest_.begin(); it != newest_.end();) {
      it = std::get<0>(it->first) == writer ? newest_.erase(it) : std::next(it);
    }
    for (auto it = reported_.begin(); it != reported_.end();) {
      it = it->first.first == writer ? reported_.erase(it) : std::next(it);
    }
    for (auto it = refused_.begin(); it != refused_.end();) {
      it = it->first == writer ? refused_.erase(it) : std::next(it);
    }
  }

 private:
  struct Reported {
    bool vocabulary = false;
    bool state = false;
    bool back = false;
    bool leap = false;
  };

  static dds::detail::Handle handle_of(std::uint8_t writer) {
    dds::detail::Handle h{};
    h[0] = 0x01;
    h[15] = static_cast<std::uint8_t>(writer + 1);
    return h;
  }
  static bool names_no_service(const core::ObservedValue& value) {
    return value.kind() == core::ItemKind::Interaction && (!value.service || !value.sub_type);
  }

  // Whether this value must be reported, by the rules, and what is known
  // afterwards.
  bool expect(std::uint8_t writer, std::size_t group, const core::ObservedValue& value) {
    auto& flags = reported_[{writer, value.data_item_id}];
    bool report = false;
    const auto once = [&report](bool& flag) {
      if (flag || report) return;
      flag = true;
      report = true;
    };
    if (names_no_service(value)) {
      once(flags.vocabulary);
      return report;
    }
    if (!value.state.in_vocabulary()) once(flags.state);
    auto& newest = newest_[{writer, group, value.data_item_id}];
    const std::uint64_t received = value.sequence_number;
    if (newest != 0 && received < newest) {
      once(flags.back);
    } else if (newest != 0 && received > newest &&
               received - newest > dds::detail::PeerChecks::kLargestPlausibleLeap) {
      once(flags.leap);
    }
    newest = received;
    return report;
  }

  dds::detail::PeerChecks checks_;
  std::map<std::tuple<std::uint8_t, std::size_t, std::string>, std::uint64_t> newest_;
  std::map<std::pair<std::uint8_t, std::string>, Reported> reported_;
  std::set<std::pair<std::uint8_t, std::size_t>> refused_;
};

}  // namespace mtc::fuzz
