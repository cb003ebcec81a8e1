// The bar feeder: serves MATERIAL_FEED (advances bar stock to the pick
// position), refusing a feed when the fault plan says so.
#include "console.hpp"
#include "station_script.hpp"

namespace mtc::cell::script {

int run_feeder(Station& c) {
  int feeds = 0;
  while (!c.stop.stopped()) {
    const auto job = c.link.wait_job({Service::MaterialFeed}, kPoll);
    if (!job) {
      recover_idle(c, {Service::MaterialFeed}, "");
      continue;
    }
    ResponsePort& port = c.link.responder(*job);
    if (c.take_fault(feeds + 1, FaultPoint::FeederRefusesFeed)) {
      announce_fault(c, "", describe(FaultPoint::FeederRefusesFeed, feeds + 1));
      port.fail();
      recover_response(c, *job, "");
      continue;
    }
    if (!port.accept()) {
      continue;
    }
    c.say("MATERIAL_FEED   ACTIVE: advancing bar stock to the pick position");
    if (!c.stop.sleep_for(c.options.pace * 2)) {
      break;
    }
    if (!port.cancelled()) {
      c.say("MATERIAL_FEED   COMPLETE");
      if (finish_job(c, port, *job, "")) {
        ++feeds;
      }
      continue;
    }
    recover_response(c, *job, "");
  }
  return 0;
}

}  // namespace mtc::cell::script
