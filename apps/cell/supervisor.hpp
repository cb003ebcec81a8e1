// How mtc-cell runs its stations.
//
// Default: one process per station (machine, robot, feeder), as on a shop
// floor where each is its own controller with its own DDS participant; a
// station that crashes or freezes is then seen by the others through DDS
// liveliness, exactly as a real controller would be. The supervisor starts
// them, forwards Ctrl-C/SIGTERM, ends the run after --cycles (when the
// machine is done) or --duration, and reaps every child before it exits.
#pragma once

#include <string>
#include <vector>

#include "cell_plan.hpp"
#include "stations.hpp"

namespace mtc::cell {

// Runs the three stations as child processes (`self --station NAME args...`).
// Returns the cell's exit code: the machine's, 0 when stopped by a signal or
// --duration, 1 when another station died.
int supervise(const CellOptions& options, const std::vector<std::string>& station_args);

// Runs one station in this process (over DDS) until it is done or signalled.
int run_station_process(StationId id, const CellOptions& options);

// Runs all three stations as threads of this process, over DDS or, with
// `local`, over the in-memory LocalBus.
int run_all_in_process(const CellOptions& options, bool local);

}  // namespace mtc::cell
