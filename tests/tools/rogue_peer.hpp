// A deliberately misbehaving piece of equipment for failure scenarios 4 and
// 5, which need a peer that breaks Tables 5/6 (request READY / response
// NOT_READY while the service is ACTIVE). The runtime refuses to publish such
// states, so the test process plays that peer itself: it publishes one
// interaction data item exactly as the runtime would (same topics, partition,
// keys and QoS, changes only, with a heartbeat) with whatever state the test
// dictates, and watches its counterpart through a DomainObserver. Its lease
// is 10 x 100 ms, the default of the `mtc` processes in these tests.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include "mtc/core/vocabulary.hpp"

namespace mtc::test {

class RoguePeer {
 public:
  // own_side: Request to impersonate a requester, Response for a responder.
  RoguePeer(int domain, const std::string& device, const std::string& interface_id,
            core::Service service, core::SubType own_side, const std::string& counterpart);
  ~RoguePeer();
  RoguePeer(const RoguePeer&) = delete;
  RoguePeer& operator=(const RoguePeer&) = delete;

  // Publishes a new value now (a change: sequence number bumped).
  void set_state(core::InteractionState state);
  // What no conforming writer sends (hostile-peer tests). set_raw_state
  // publishes a state number as given, inside the vocabulary or not;
  // set_next_sequence publishes `state` as change number `next` (a counter
  // that leaps or goes back). set_raw_service / set_service only set the
  // service number of the samples that follow.
  void set_raw_state(std::int32_t raw);
  void set_next_sequence(std::uint64_t next, core::InteractionState state);
  void set_raw_service(std::int32_t raw);
  void set_service(core::Service service);
  // Waits until the counterpart's item of the same service changes to
  // `state` (after the change matched by the previous wait).
  bool wait_counterpart(core::InteractionState state, std::chrono::milliseconds timeout);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mtc::test
