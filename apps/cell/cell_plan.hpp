// The cell's fixed layout (who requests what from whom) and its seeded fault
// schedule. Pure functions of (seed, cycle): every station process computes
// the same plan on its own, so no extra coordination is needed on the wire.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "mtc/core/vocabulary.hpp"

namespace mtc::cell {

enum class StationId : std::uint8_t { Machine, Robot, Feeder };

std::string_view to_string(StationId id) noexcept;
std::optional<StationId> parse_station(std::string_view text) noexcept;

// One injected failure per point, each a scenario of Part 5 section 5.1.
// Scenarios 4 and 5 (a side jumping to READY / NOT_READY mid-service) are
// protocol violations a conforming runtime refuses to publish, so the cell
// cannot stage them; the core and runtime tests cover them instead.
enum class FaultPoint : std::uint8_t {
  FeederRefusesFeed,         // 1: feeder FAIL right after MATERIAL_FEED went ACTIVE
  RobotDropsPartOnLoad,      // 2: robot FAIL while performing MATERIAL_LOAD
  MachineStopsDuringUnload,  // 3: machine FAIL on its MATERIAL_UNLOAD request
  DoorJams,                  // 2: machine's OPEN_DOOR response FAIL while opening
  RobotCollisionAtChuck,     // 3: robot FAIL on its OPEN_CHUCK request
};
inline constexpr int kFaultPointCount = 5;

struct Fault {
  int cycle = 0;
  FaultPoint point = FaultPoint::FeederRefusesFeed;
  StationId party = StationId::Feeder;                  // who fails
  core::Service service = core::Service::MaterialFeed;  // whose handshake fails
  int scenario = 1;                                     // Part 5 section 5.1 scenario number
  std::string_view what;                                // the simulated cause, for the log
};

Fault describe(FaultPoint point, int cycle) noexcept;

// The step of the machine's cycle (MATERIAL_FEED, _LOAD or _UNLOAD) a fault
// makes fail. Every injected fault ends in exactly one failed machine step,
// also those that hit the robot's door or chuck request (the robot then
// fails its load, scenario 2), so the machine can tell the failures its plan
// explains from any other (a false loss alarm, a timeout).
core::Service machine_step_failed_by(FaultPoint point) noexcept;

// One fault in every block of `every` cycles, at a seeded position within the
// block; the fault points take turns so a long run shows every scenario.
// every <= 0: never.
class FaultPlan {
 public:
  FaultPlan(std::uint64_t seed, int every) noexcept : seed_(seed), every_(every) {}
  std::optional<Fault> at(int cycle) const noexcept;
  // The fault of `cycle`, if it is `point`'s turn.
  bool hits(int cycle, FaultPoint point) const noexcept;

 private:
  std::uint64_t seed_;
  int every_;
};

}  // namespace mtc::cell
