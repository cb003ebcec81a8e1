#include "cell_plan.hpp"

namespace mtc::cell {
namespace {

// splitmix64: a tiny, well-mixed hash, identical on every platform (unlike
// std::uniform_int_distribution), so all stations agree on the plan.
std::uint64_t mix(std::uint64_t x) noexcept {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

}  // namespace

std::string_view to_string(StationId id) noexcept {
  switch (id) {
    case StationId::Machine:
      return "machine";
    case StationId::Robot:
      return "robot";
    case StationId::Feeder:
      return "feeder";
  }
  return "?";
}

std::optional<StationId> parse_station(std::string_view text) noexcept {
  for (auto id : {StationId::Machine, StationId::Robot, StationId::Feeder}) {
    if (text == to_string(id)) {
      return id;
    }
  }
  return std::nullopt;
}

Fault describe(FaultPoint point, int cycle) noexcept {
  using core::Service;
  switch (point) {
    case FaultPoint::FeederRefusesFeed:
      return {cycle, point, StationId::Feeder, Service::MaterialFeed, 1, "no bar stock detected"};
    case FaultPoint::RobotDropsPartOnLoad:
      return {cycle, point, StationId::Robot, Service::MaterialLoad, 2, "gripper lost the part"};
    case FaultPoint::MachineStopsDuringUnload:
      return {cycle,
              point,
              StationId::Machine,
              Service::MaterialUnload,
              3,
              "spindle alarm, machine stops the unload"};
    case FaultPoint::DoorJams:
      return {cycle, point, StationId::Machine, Service::OpenDoor, 2, "door jammed half open"};
    case FaultPoint::RobotCollisionAtChuck:
      return {cycle,
              point,
              StationId::Robot,
              Service::OpenChuck,
              3,
              "collision sensor tripped at the chuck"};
  }
  return {};
}

core::Service machine_step_failed_by(FaultPoint point) noexcept {
  switch (point) {
    case FaultPoint::FeederRefusesFeed:
      return core::Service::MaterialFeed;
    case FaultPoint::MachineStopsDuringUnload:
      return core::Service::MaterialUnload;
    case FaultPoint::RobotDropsPartOnLoad:
    case FaultPoint::DoorJams:  // the first OPEN_DOOR of a cycle belongs to its load
    case FaultPoint::RobotCollisionAtChuck:
      return core::Service::MaterialLoad;
  }
  return core::Service::MaterialLoad;
}

std::optional<Fault> FaultPlan::at(int cycle) const noexcept {
  if (every_ <= 0 || cycle <= 0) {
    return std::nullopt;
  }
  const auto block = static_cast<std::uint64_t>((cycle - 1) / every_);
  const auto position = static_cast<int>(mix(seed_ ^ (block << 1)) % static_cast<unsigned>(every_));
  if ((cycle - 1) % every_ != position) {
    return std::nullopt;
  }
  const auto first = mix(seed_) % kFaultPointCount;
  const auto turn = static_cast<int>((first + block) % kFaultPointCount);
  return describe(static_cast<FaultPoint>(turn), cycle);
}

bool FaultPlan::hits(int cycle, FaultPoint point) const noexcept {
  const auto fault = at(cycle);
  return fault && fault->point == point;
}

}  // namespace mtc::cell
