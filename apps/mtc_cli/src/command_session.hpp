// What the `mtc` commands do alike once their options are parsed: say that
// they started and, for `request` and `respond`, bring up the equipment,
// run their loop on this thread and tear down in order. Each cmd_*.cpp
// keeps only what is its own (options, start notice, loop).
#pragma once

#include <functional>
#include <string>

#include "commands.hpp"
#include "equipment_link.hpp"
#include "link_events.hpp"
#include "mtc/core/vocabulary.hpp"
#include "output.hpp"

namespace mtc::cli {

// How a command says it has started: with --json one event on stdout (the
// first line a script reads), otherwise a line on stderr, so that stdout
// carries only what the command reports.
struct StartNotice {
  JsonLine json;
  std::string text;
};

void announce(Context& context, bool json, const StartNotice& notice);

// The command's loop over an equipment that is up: pops events from
// `events`, drives `link`, returns the exit code.
using EquipmentLoop = std::function<int(EquipmentLink& link, EventQueue& events)>;

// `mtc request` and `mtc respond`: creates the equipment (EquipmentLink,
// throws mtc::dds::Error) with its event queue, lets a shutdown request
// wake that queue, announces `notice` once the equipment is up, runs
// `loop` and returns its exit code. The shutdown listener is removed before
// the queue goes away, on every path.
int run_with_equipment(const EquipmentConfig& equipment, core::Role role, const StartNotice& notice,
                       Context& context, const EquipmentLoop& loop);

}  // namespace mtc::cli
