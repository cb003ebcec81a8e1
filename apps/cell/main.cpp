// mtc-cell: a simulated machine-tending cell -- machine tool, robot and bar
// feeder -- running Part 5 load/unload cycles over DDS, with seeded failures
// that recover. `./scripts/start.sh` runs it with the MTConnect bridge.
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "cell_plan.hpp"
#include "equipment_link.hpp"
#include "mtc/qos/participant.hpp"
#include "stations.hpp"
#include "supervisor.hpp"

namespace {

using mtc::cell::CellOptions;

void usage(std::ostream& out) {
  const mtc::qos::Timing defaults;
  out << "usage: mtc-cell [options]\n"
         "  --cycles N       stop after N machine cycles (default: run until Ctrl-C)\n"
         "  --duration S     stop after S seconds\n"
         "  --seed N         seed of the failure schedule (default 1)\n"
         "  --fail-every K   one injected failure per K cycles, 0 = none (default 10)\n"
         "  --pace-ms MS     duration of one simulated motion (default 150)\n"
         "  --comms-loss-every S\n"
         "                   about every S seconds freeze the robot or the feeder (SIGSTOP)\n"
         "                   for a lease + 3 s: scenario 6 (default 0 = never; processes only)\n"
         "  --domain D       DDS domain id (default 110)\n"
         "  --transport KIND network (UDP on every interface + SHM: stations on several\n"
         "                   hosts), loopback (UDP 127.0.0.1 + SHM: this host only) or\n"
         "                   loopback-udp (default "
      << mtc::qos::to_string(CellOptions{}.transport)
      << ")\n"
         "  --heartbeat-ms MS, --missed-heartbeats N\n"
         "                   DDS heartbeat and loss detection (default "
      << defaults.heartbeat.count() << " x " << defaults.missed_heartbeats << " = "
      << defaults.lease().count()
      << " ms)\n"
         "  --middleware NAME, --middleware STATION=NAME\n"
         "                   DDS implementation of every station, or of one (repeat it):\n"
         "                   fastdds (default) or cyclone, e.g. --middleware robot=cyclone\n"
         "  --security DIR   DDS-Security: DIR is the make-pki.sh output for\n"
         "                   scripts/security/cell.txt; each station uses DIR/<its uuid>\n"
         "  --threads        run the three stations as threads of one process\n"
         "  --local          same, over an in-memory link instead of DDS (no network)\n"
         "  --station NAME   run one station only: machine, robot or feeder\n"
         "Runs inside the loopback-only namespace: ./scripts/start.sh does that.\n";
}

bool parse_number(const std::string& text, long min, long max, long& out) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || v < min || v > max) {
    return false;
  }
  out = v;
  return true;
}

enum class Mode { Supervise, Station, Threads, Local };

struct Parsed {
  CellOptions options;
  Mode mode = Mode::Supervise;
  mtc::cell::StationId station = mtc::cell::StationId::Machine;
  std::vector<std::string> station_args;  // what each child station gets
};

// --middleware NAME (every station) or STATION=NAME (one): an error message,
// empty when taken.
std::string parse_middleware(const std::string& v, mtc::cell::CellOptions& options) {
  const auto equals = v.find('=');
  const std::string name = equals == std::string::npos ? v : v.substr(equals + 1);
  const auto choice = mtc::dds::choose_middleware(name);
  if (!choice.middleware) return "--middleware: " + choice.problem;
  const auto middleware = *choice.middleware;
  if (equals == std::string::npos) {
    options.middleware.fill(middleware);
    return {};
  }
  const auto station = mtc::cell::parse_station(v.substr(0, equals));
  if (!station) return "unknown station in --middleware '" + v + "' (machine, robot or feeder)";
  options.middleware[static_cast<std::size_t>(*station)] = middleware;
  return {};
}

// The options whose value is a name (--station, --transport, --middleware):
// true when `a` was one of them, with `error` set when its value is unknown.
bool parse_named_value(const std::string& a, const std::string& v, Parsed& p, std::string& error) {
  if (a == "--middleware") {
    error = parse_middleware(v, p.options);
    p.station_args.push_back(a);
    p.station_args.push_back(v);
    return true;
  }
  if (a == "--station") {
    const auto id = mtc::cell::parse_station(v);
    if (!id) {
      error = "unknown station '" + v + "' (machine, robot or feeder)";
      return true;
    }
    p.mode = Mode::Station;
    p.station = *id;
    return true;
  }
  if (a == "--transport") {
    const auto transport = mtc::qos::parse_transport(v);
    if (!transport) {
      error = "unknown transport '" + v + "' (network, loopback or loopback-udp)";
      return true;
    }
    p.options.transport = *transport;
    p.station_args.push_back(a);
    p.station_args.push_back(v);
    return true;
  }
  return false;
}

// Returns an error message, empty on success.
std::string parse(int argc, char** argv, Parsed& p) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--threads") {
      p.mode = Mode::Threads;
      continue;
    }
    if (a == "--local") {
      p.mode = Mode::Local;
      continue;
    }
    if (i + 1 >= argc) {
      return "unknown option or missing value: " + a;
    }
    const std::string v = argv[++i];
    long n = 0;
    std::string error;
    if (parse_named_value(a, v, p, error)) {
      if (!error.empty()) return error;
      continue;
    }
    if (a == "--security" && !v.empty()) {
      p.options.security_dir = v;
    } else if (a == "--cycles" && parse_number(v, 0, 1000000, n)) {
      p.options.cycles = static_cast<int>(n);
    } else if (a == "--duration" && parse_number(v, 0, 86400L * 365, n)) {
      p.options.duration_s = static_cast<int>(n);
      continue;  // the supervisor's business, not the stations'
    } else if (a == "--comms-loss-every" && parse_number(v, 0, 86400, n)) {
      p.options.freeze_every_s = static_cast<int>(n);
      continue;  // staged by the supervisor
    } else if (a == "--seed" && parse_number(v, 0, 2147483647, n)) {
      p.options.seed = static_cast<std::uint64_t>(n);
    } else if (a == "--fail-every" && parse_number(v, 0, 1000000, n)) {
      p.options.fail_every = static_cast<int>(n);
    } else if (a == "--pace-ms" && parse_number(v, 1, 60000, n)) {
      p.options.pace = mtc::cell::Millis(n);
    } else if (a == "--heartbeat-ms" && parse_number(v, 10, 60000, n)) {
      p.options.timing.heartbeat = mtc::cell::Millis(n);
    } else if (a == "--missed-heartbeats" && parse_number(v, 2, 100, n)) {
      p.options.timing.missed_heartbeats = static_cast<int>(n);
    } else if (a == "--domain" && parse_number(v, 0, 232, n)) {
      p.options.domain_id = static_cast<int>(n);
    } else {
      // Built once, on the way out of the loop.
      // NOLINTNEXTLINE(performance-inefficient-string-concatenation)
      return "bad option or value: " + a + " " + v;
    }
    p.station_args.push_back(a);
    p.station_args.push_back(v);
  }
  return {};
}

}  // namespace

int main(int argc, char** argv) {
  // A shell starts background jobs with SIGINT ignored, and an ignored
  // disposition survives exec: take the defaults back so Ctrl-C and SIGTERM
  // reach the supervisor's and stations' sigwait.
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      usage(std::cout);
      return 0;
    }
  }
  Parsed p;
  const std::string error = parse(argc, argv, p);
  if (!error.empty()) {
    std::cerr << "mtc-cell: " << error << "\n";
    usage(std::cerr);
    return 2;
  }
  if (!p.options.security_dir.empty()) {
    for (auto id : {mtc::cell::StationId::Machine, mtc::cell::StationId::Robot,
                    mtc::cell::StationId::Feeder}) {
      const auto dir = mtc::cell::security_dir_of(id, p.options);
      if (auto problem = mtc::qos::check_security_dir(dir)) {
        std::cerr << "mtc-cell: --security: " << *problem << "\n";
        return 2;
      }
    }
  }
  switch (p.mode) {
    case Mode::Station:
      return mtc::cell::run_station_process(p.station, p.options);
    case Mode::Threads:
      return mtc::cell::run_all_in_process(p.options, false);
    case Mode::Local:
      return mtc::cell::run_all_in_process(p.options, true);
    case Mode::Supervise:
      break;
  }
  return mtc::cell::supervise(p.options, p.station_args);
}
