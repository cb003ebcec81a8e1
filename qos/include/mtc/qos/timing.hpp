// Timing of one interface's heartbeat and of comms-loss detection.
//
// MTConnect asks each piece of equipment for a heartbeat so that its peer can
// tell "nothing changed" from "gone". On DDS the heartbeat is one small sample
// per device and timing group per period on its own topic (mtc/Heartbeat);
// data items are written only when they change. DEADLINE and MANUAL_BY_TOPIC
// liveliness on the heartbeat topic turn a missing heartbeat into an event
// within `lease()`.
#pragma once

#include <chrono>

namespace mtc::qos {

struct Timing {
  // Application heartbeat: each timing group of a device writes one
  // heartbeat sample this often. 100 ms keeps a machine handshake's detection
  // time well under a second while costing 10 small samples per second per
  // device and reader, whatever its number of data items.
  std::chrono::milliseconds heartbeat{100};

  // A peer is declared lost after this many heartbeat periods without a
  // heartbeat (DEADLINE period and liveliness lease). 3 tolerates two late
  // heartbeats plus scheduling jitter before raising a false alarm; reliable
  // retransmission repairs a lost one within `reliable_heartbeat`.
  int missed_heartbeats = 3;

  // RTPS reliable-writer HEARTBEAT period: how soon a reader learns that it
  // missed a sample and asks for a repair. Fast DDS defaults to 3 s, which
  // makes one lost packet cost seconds; 20 ms makes it cost milliseconds.
  std::chrono::milliseconds reliable_heartbeat{20};

  // Participant discovery lease and announcement period. Fast DDS defaults
  // (20 s / 3 s) would keep a dead peer's endpoints matched for 20 s and
  // delay rediscovery after a cable pull by up to 3 s.
  std::chrono::milliseconds participant_lease{2000};
  std::chrono::milliseconds participant_announcement{500};

  // DEADLINE period and liveliness lease derived from the heartbeat.
  constexpr std::chrono::milliseconds lease() const noexcept {
    return heartbeat * missed_heartbeats;
  }
};

// Throws std::invalid_argument with the reason when the timing cannot work
// (non-positive periods, fewer than 2 missed heartbeats, participant lease
// not longer than its announcement period, ...).
void validate(const Timing& timing);

}  // namespace mtc::qos
