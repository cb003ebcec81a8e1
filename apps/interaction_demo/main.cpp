// mtc-interaction-demo: plays the MTConnect Part 5 interaction model between
// a machine tool (requester of MATERIAL_LOAD) and a robot (responder), using
// the pure state machines of mtc::core on a simulated clock, and prints every
// transition of a success run and of failure scenarios 1-6.
#include <cstdio>
#include <string>
#include <string_view>

#include "scenarios.hpp"

namespace {

using mtc::core::Profile;

void usage(std::FILE* out) {
  std::fprintf(out,
               "usage: mtc-interaction-demo [--profile 1.6|1.8|1.3|all] [--scenario N|all]\n"
               "\n"
               "Plays a requester (cnc) and a responder (robot) of MTConnect Part 5\n"
               "Interfaces against each other on a simulated clock and prints every\n"
               "transition: time, side, data item, event, old -> new state, notice.\n"
               "\n"
               "  --profile   1.6 (same model as 1.8), 1.3, or all (default: 1.6 for\n"
               "              every scenario, then 1.3 where the 1.3 text differs)\n"
               "  --scenario  0 = success run (Table 1), 1-6 = section 5.1 failure\n"
               "              scenarios, 7 = time limits, all (default)\n"
               "  --help      this text\n");
}

struct Options {
  bool v16 = true;
  bool v13 = true;
  bool only_differences_13 = true;
  int scenario = -1;  // -1 = all
};

enum class Parsed { Run, Help, Bad };

// On Parsed::Bad, `bad` holds the argument at fault.
Parsed parse(int argc, char** argv, Options& o, std::string_view& bad) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    bad = arg;
    const bool has_value = i + 1 < argc;
    if (arg == "--help" || arg == "-h") {
      return Parsed::Help;
    }
    if (arg == "--profile" && has_value) {
      const std::string_view v = bad = argv[++i];
      if (v == "1.6" || v == "1.8") {
        o.v13 = false;
      } else if (v == "1.3") {
        o.v16 = false;
        o.only_differences_13 = false;
      } else if (v != "all") {
        return Parsed::Bad;
      }
    } else if (arg == "--scenario" && has_value) {
      const std::string_view v = bad = argv[++i];
      if (v == "all") continue;
      if (v.size() != 1 || v[0] < '0' || v[0] > '7') return Parsed::Bad;
      o.scenario = v[0] - '0';
    } else {
      return Parsed::Bad;
    }
  }
  return Parsed::Run;
}

void play(const mtc::demo::Scenario& s, Profile p) {
  std::printf("\n=== %s [MTConnect %s] ===\n    %s\n", s.title,
              p == Profile::V1_3 ? "1.3" : "1.6/1.8", s.summary);
  s.run(p);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  std::string_view bad;
  switch (parse(argc, argv, o, bad)) {
    case Parsed::Help:
      usage(stdout);
      return 0;
    case Parsed::Bad:
      std::fprintf(stderr, "mtc-interaction-demo: unknown option, missing or bad value: '%.*s'\n\n",
                   static_cast<int>(bad.size()), bad.data());
      usage(stderr);
      return 2;
    case Parsed::Run:
      break;
  }
  std::printf(
      "MTConnect Part 5 interaction model: cnc requests MATERIAL_LOAD, robot responds.\n"
      "Columns: simulated time, side, data item, event, old -> new state, notice.\n");
  for (const auto& s : mtc::demo::scenarios()) {
    if (o.scenario >= 0 && s.number != o.scenario) continue;
    if (o.v16) play(s, Profile::V1_6);
    const bool explicit_choice = o.scenario >= 0 || !o.only_differences_13;
    if (o.v13 && (s.differs_in_1_3 || explicit_choice)) play(s, Profile::V1_3);
  }
  return 0;
}
