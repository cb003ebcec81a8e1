// What the `path` budget still allows: every XPath that estimate_path_cost
// accepts is evaluated and timed, on the sample cell and on models 10 and
// 100 times its size, for a fixed list of client and adversarial shapes and
// for random expressions over the XPath grammar. The slowest accepted one is
// the worst a request can cost the bridge (docs/bridge.md). Expressions just
// over the budget are timed too, to show the estimate bounds the real cost.
//
// Prints one JSON line:
//   {"benchmark":"bridge_path_cost","max_visits",...,"models":[{"name","nodes",
//    "accepted","refused","worst_accepted_ms","worst_expression",
//    "max_ns_per_estimated_visit"}...],"worst_accepted_ms"}
#include <algorithm>
#include <chrono>
#include <ctime>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "mtc/bench/cli.hpp"
#include "mtc/bridge/device_model.hpp"

namespace {

namespace core = mtc::core;
using mtc::bridge::DeviceModel;
using mtc::bridge::estimate_path_cost;
using mtc::bridge::PathCost;
using mtc::bridge::PathLimits;
using mtc::bridge::SchemaVersion;
using mtc::bridge::SlotRegistry;

constexpr const char* kAbout =
    "Times every XPath `path` filter the bridge's cost estimate accepts (fixed client and\n"
    "adversarial shapes, then random expressions) on the sample cell and on models 10\n"
    "and 100 times larger; prints the slowest accepted evaluation and the largest time\n"
    "per estimated node visit as one JSON line on stdout. No DDS, no sockets.";

core::ObservedDataItem item(std::string id, std::string type, std::string sub = "") {
  core::ObservedDataItem d;
  d.id = std::move(id);
  d.type = std::move(type);
  d.sub_type = std::move(sub);
  d.category = "EVENT";
  return d;
}

// `copies` times a mill, a robot and a feeder, as announced over DDS.
DeviceModel announced_cell(int copies, SlotRegistry& slots) {
  std::vector<core::ObservedDevice> devices;
  for (int i = 0; i < copies; ++i) {
    const std::string n = std::to_string(i);
    for (const char* kind : {"mill", "robot", "feeder"}) {
      core::ObservedDevice d;
      d.device_uuid = std::string(kind) + "-" + n;
      d.name = d.device_uuid;
      core::ObservedInterface door{"door", "door", core::InterfaceType::Door, {}};
      door.data_items = {item("door_state", "INTERFACE_STATE"),
                         item("door_open", "OPEN_DOOR", "REQUEST"),
                         item("door_close", "CLOSE_DOOR", "REQUEST")};
      core::ObservedInterface mh{"mh", "mh", core::InterfaceType::MaterialHandler, {}};
      mh.data_items = {item("mh_state", "INTERFACE_STATE"),
                       item("mh_load", "MATERIAL_LOAD", "RESPONSE"),
                       item("mh_unload", "MATERIAL_UNLOAD", "RESPONSE")};
      d.interfaces = {door, mh};
      devices.push_back(d);
    }
  }
  return DeviceModel::from_announcements(devices, SchemaVersion::V1_6, slots);
}

// Random expressions over the XPath grammar, biased to the costly parts:
// descendant and following axes, nested predicates, count(), comparisons.
class Generator {
 public:
  explicit Generator(unsigned seed) : random_(seed) {}
  std::string path(int depth) {
    std::string out = pick({"//", "/", "//", ""});
    const int steps = 1 + next(3);
    for (int i = 0; i < steps; ++i) {
      if (i > 0) out += pick({"/", "//"});
      out += step(depth);
    }
    return out;
  }

 private:
  int next(int n) { return std::uniform_int_distribution<int>(0, n - 1)(random_); }
  std::string pick(std::initializer_list<const char*> choices) {
    return *(choices.begin() + next(static_cast<int>(choices.size())));
  }
  std::string step(int depth) {
    std::string s = pick({"", "", "", "descendant::", "following::", "ancestor::", "parent::",
                          "preceding-sibling::", "self::"});
    s += pick({"*", "DataItem", "Device", "Components", "DoorInterface", "node()", "*"});
    if (depth > 0 && next(2) == 0) s += "[" + predicate(depth - 1) + "]";
    return s;
  }
  std::string predicate(int depth) {
    switch (next(8)) {
      case 0:
        return "@type='OPEN_DOOR'";
      case 1:
        return "count(" + path(depth) + ") > " + std::to_string(next(5));
      case 2:
        return path(depth);
      case 3:
        return "not(" + path(depth) + ")";
      case 4:
        return "contains(@id, 'door')";
      case 5:
        return ". = " + path(depth);
      case 6:
        return path(depth) + " = " + path(depth);
      default:
        return "string-length(concat(@id, " + path(depth) + ")) > 3";
    }
  }
  std::mt19937 random_;
};

// Below this, a select() is its fixed cost (compiling the query), not visits.
constexpr double kFloorMs = 0.5;

struct Timing {
  double ms = 0;
  double ns_per_visit = 0;
};

// CPU time of this thread, in ms: the machine is shared, and time spent
// preempted says nothing about the expression.
double thread_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) / 1e6;
}

// The fastest of up to five runs (cache and allocator warm).
Timing time_select(const DeviceModel& model, const std::string& xpath, const PathLimits& limits,
                   double visits) {
  double best = 1e300;
  double spent = 0;
  for (int run = 0; run < 5 && spent < 200; ++run) {
    const double t0 = thread_cpu_ms();
    try {
      (void)model.select(xpath, std::nullopt, limits);
    } catch (const std::invalid_argument&) {  // pugixml: a type error, e.g.
    }
    const double ms = thread_cpu_ms() - t0;
    best = std::min(best, ms);
    spent += ms;
  }
  return {best, best * 1e6 / std::max(1.0, visits)};
}

std::string json_string(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// What one model allows: every expression estimated, the accepted ones
// timed, and those just over the budget timed for calibration.
struct ModelFigures {
  int accepted = 0;
  int refused = 0;
  Timing worst;
  std::string worst_expression;
  double worst_ratio = 0;
  std::string worst_ratio_expression;

  void record_ratio(const Timing& t, const std::string& xpath) {
    if (t.ms >= kFloorMs && t.ns_per_visit > worst_ratio) {
      worst_ratio = t.ns_per_visit;
      worst_ratio_expression = xpath;
    }
  }
};

ModelFigures measure(const DeviceModel& model, const std::vector<std::string>& expressions,
                     const PathLimits& limits) {
  ModelFigures f;
  // select() walks every node once more to collect the DataItems.
  const auto nodes = static_cast<double>(model.shape().nodes);
  PathLimits open = limits;  // nesting is not what is measured here
  open.max_nesting = 64;
  PathLimits xpath_only = open;  // what select() leaves to the XPath
  xpath_only.max_visits -= nodes;
  for (const std::string& xpath : expressions) {
    const PathCost cost = estimate_path_cost(xpath, model.shape(), xpath_only);
    const double visits = cost.visits + nodes;
    if (!cost.accepted) {
      ++f.refused;
      // Just over the budget: timed too (calibration), never the absurd.
      if (cost.visits > 0 && visits < 10.0 * limits.max_visits) {
        PathLimits over = open;
        over.max_visits = 1e12;
        f.record_ratio(time_select(model, xpath, over, visits), xpath);
      }
      continue;
    }
    ++f.accepted;
    const Timing t = time_select(model, xpath, open, visits);
    f.record_ratio(t, xpath);
    if (t.ms > f.worst.ms) {
      f.worst = t;
      f.worst_expression = xpath;
    }
  }
  return f;
}

const std::vector<std::string> kFixed{
    "//DataItem[@type='OPEN_DOOR']",
    "//Device[@name='mill-0']//DataItem",
    "//DataItem[contains(@id,'door')]",
    "//*[@type='AVAILABILITY']",
    "//*",
    "//node()",
    "//*[count(//*) > 1]",
    "//*[. = 'x']",
    "//*[following::*]",
    "//*[count(ancestor::*) > 3]",
    "//*[count(//*[count(//*) > 1]) > 1]",
    "//*[count(//*[count(//*[count(//*[count(//*[count(//*)])])])])]"};

}  // namespace

int main(int argc, char** argv) try {
  int random_count = 3000;
  int max_visits = 2'000'000;
  mtc::bench::Cli cli("mtc-bench-bridge-path-cost", kAbout);
  cli.integer("--random", random_count, 0, 1000000, "random expressions per model")
      .integer("--max-visits", max_visits, 1000, 1000000000, "PathLimits::max_visits");
  if (const auto exit_code = cli.parse(argc, argv)) return *exit_code;

  PathLimits limits;
  limits.max_visits = max_visits;
  std::ostringstream models;
  double worst_overall = 0;
  for (const int copies : {1, 10, 100, 1000}) {
    SlotRegistry slots;
    const DeviceModel model = announced_cell(copies, slots);
    Generator generator(7);
    std::vector<std::string> expressions = kFixed;
    for (int i = 0; i < random_count; ++i) expressions.push_back(generator.path(3));
    const ModelFigures f = measure(model, expressions, limits);
    worst_overall = std::max(worst_overall, f.worst.ms);
    models << (copies == 1 ? "" : ",") << "{\"name\":\"cell_x" << copies
           << "\",\"nodes\":" << model.shape().nodes << ",\"accepted\":" << f.accepted
           << ",\"refused\":" << f.refused << ",\"worst_accepted_ms\":" << f.worst.ms
           << ",\"worst_expression\":" << json_string(f.worst_expression)
           << ",\"max_ns_per_estimated_visit\":" << f.worst_ratio
           << ",\"max_ratio_expression\":" << json_string(f.worst_ratio_expression) << "}";
  }
  std::cout << "{\"benchmark\":\"bridge_path_cost\",\"max_visits\":" << max_visits
            << ",\"models\":[" << models.str() << "],\"worst_accepted_ms\":" << worst_overall << "}"
            << std::endl;
  return 0;
} catch (const std::exception& e) {
  std::cerr << "mtc-bench-bridge-path-cost: " << e.what() << "\n";
  return 1;
}
