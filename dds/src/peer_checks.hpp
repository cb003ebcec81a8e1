// Internal: rules a peer's samples must keep that the IDL types cannot
// express, checked where a value is received (issue 10, hostile peers).
//   - a state outside its item's vocabulary (reported here by name; an
//     interaction machine also fails its service on it, Table 5/6's
//     protocol violation, and the bridge shows UNAVAILABLE);
//   - an interaction sample whose service or sub-type is outside the
//     vocabulary (it names no service, so no machine can take it);
//   - a change number that goes back for the same writer and item (a
//     writer's counter only grows; a restarted device is a new writer), or
//     that leaps ahead by more than any real writer could change between
//     two deliveries (a counter jumped to the maximum);
//   - a sample whose service or side disagrees with its interaction topic
//     (the tap refuses it; refused() says so once per writer and topic).
// Each rule is reported once per writer and item, so a peer that floods the
// topic cannot flood the log as well; the value itself is still handled as
// the rules below say (check()'s verdict).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "lookup_keys.hpp"
#include "mw/tap_events.hpp"

namespace mtc::dds::detail {

class PeerChecks {
 public:
  // A change number may skip what KEEP_LAST 1 replaced before delivery, but
  // not 2^32 changes at once: at a million changes a second that is over an
  // hour without a single delivery.
  static constexpr std::uint64_t kLargestPlausibleLeap = std::uint64_t{1} << 32;

  struct Verdict {
    bool use = true;                    // false: drop the value (no machine can take it)
    std::optional<std::string> report;  // set the first time a rule is broken
  };

  // `group`: the local timing group whose reader delivered the sample (each
  // group's reader sees every sample, and each checks its own copy).
  Verdict check(std::size_t group, const Handle& writer, const ObservedValue& value);
  // A sample the tap refused (its service or side disagrees with its
  // interaction topic): the report the first time per writer and topic.
  std::optional<std::string> refused(const ProtocolViolationEvent& event);
  // Drops what is known of a writer that left.
  void forget_writer(const Handle& writer);

 private:
  struct Reported {
    bool state = false;
    bool vocabulary = false;
    bool back = false;
    bool leap = false;
  };
  // What is known of one writer's item: reports whichever group saw it, and
  // change numbers per local group (each group's reader gets its own copy,
  // at its own pace; there are few groups, searched in order).
  struct ItemRecord {
    Reported reported;
    std::vector<std::pair<std::size_t, std::uint64_t>> newest;
    std::uint64_t& newest_of(std::size_t group);
  };
  // Per writer, then per item. Every item of a writer has the same writer
  // key, so one map keyed by (writer, item) compared the 16 bytes of the
  // writer again at every step of every search; this runs for every sample.
  // Items are hashed: a writer of 100 interfaces has hundreds of items whose
  // ids share long prefixes, and a tree compared them ten times a sample.
  std::map<Handle, std::unordered_map<std::string, ItemRecord>> items_;
  std::set<std::pair<Handle, std::size_t>> refused_;  // writer, interaction topic
};

}  // namespace mtc::dds::detail
