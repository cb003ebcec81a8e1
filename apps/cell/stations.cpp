// The Stopper, and run_station() handing a station to its script
// (machine_station.cpp, robot_station.cpp, feeder_station.cpp).
#include "stations.hpp"

#include "station_script.hpp"

namespace mtc::cell {

void Stopper::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopped_ = true;
  }
  cv_.notify_all();
}

bool Stopper::stopped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stopped_;
}

bool Stopper::sleep_for(Millis d) {
  std::unique_lock<std::mutex> lock(mutex_);
  return !cv_.wait_for(lock, d, [this] { return stopped_; });
}

int run_station(StationId id, Link& link, const CellOptions& options, Stopper& stop) {
  script::Station c{id, link, options, stop, FaultPlan(options.seed, options.fail_every), {}};
  switch (id) {
    case StationId::Machine:
      return script::run_machine(c);
    case StationId::Robot:
      return script::run_robot(c);
    case StationId::Feeder:
      return script::run_feeder(c);
  }
  return 2;
}

}  // namespace mtc::cell
