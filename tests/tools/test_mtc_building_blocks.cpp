// Unit tests of the `mtc` tool's building blocks that need no process and no
// DDS: option parsing, durations, service names, failure-injection plans and
// the JSON lines the cross-process tests rely on.
#include <gtest/gtest.h>

#include <set>

#include "cli_args.hpp"
#include "equipment_options.hpp"
#include "fail_injection.hpp"
#include "json_field.hpp"
#include "mtc/qos/presets.hpp"
#include "output.hpp"
#include "profiles.hpp"

namespace mtc::cli {
namespace {

CommandSpec sample_spec() {
  CommandSpec spec;
  spec.name = "sample";
  spec.options = {
      {"count", "N", "", ""}, {"json", "", "", ""}, {"device", "UUID", "", "", false, true}};
  return spec;
}

TEST(CliArgs, AcceptsSpaceAndEqualsFormsSwitchesAndRepeats) {
  const auto args =
      parse_args(sample_spec(), {"--count", "3", "--json", "--device=a", "--device", "b"});
  EXPECT_EQ(args.value("count"), "3");
  EXPECT_TRUE(args.has("json"));
  EXPECT_EQ(args.values("device"), (std::vector<std::string>{"a", "b"}));
  EXPECT_FALSE(args.has("missing"));
}

TEST(CliArgs, RejectsUnknownMissingDuplicateAndStray) {
  EXPECT_THROW(parse_args(sample_spec(), {"--colour"}), UsageError);
  EXPECT_THROW(parse_args(sample_spec(), {"--count"}), UsageError);
  EXPECT_THROW(parse_args(sample_spec(), {"--count", "1", "--count", "2"}), UsageError);
  EXPECT_THROW(parse_args(sample_spec(), {"stray"}), UsageError);
  EXPECT_THROW(parse_args(sample_spec(), {"--json=yes"}), UsageError);
}

TEST(CliArgs, ConvertsNumbersAndDurationsWithRanges) {
  EXPECT_EQ(to_int("n", "42", 0, 100), 42);
  EXPECT_THROW(to_int("n", "101", 0, 100), UsageError);
  EXPECT_THROW(to_int("n", "4x", 0, 100), UsageError);
  EXPECT_DOUBLE_EQ(to_double("p", "0.25", 0, 1), 0.25);
  EXPECT_THROW(to_double("p", "nan", 0, 1), UsageError);
  EXPECT_EQ(to_duration("t", "250ms").count(), 250);
  EXPECT_EQ(to_duration("t", "2").count(), 2000);
  EXPECT_EQ(to_duration("t", "1.5s").count(), 1500);
  EXPECT_EQ(to_duration("t", "1m").count(), 60000);
  EXPECT_THROW(to_duration("t", "soon"), UsageError);
  EXPECT_THROW(to_duration("t", "-1s"), UsageError);
  EXPECT_THROW(to_duration("t", "5h"), UsageError);
}

TEST(CliArgs, HelpListsVisibleOptionsOnly) {
  CommandSpec spec = sample_spec();
  spec.options.push_back({"secret", "X", "hidden knob", "", true});
  const std::string help = format_help(spec);
  EXPECT_NE(help.find("--count N"), std::string::npos) << help;
  EXPECT_EQ(help.find("--secret"), std::string::npos) << help;
}

TEST(Services, ParsesNamesListsAndAll) {
  EXPECT_EQ(parse_services("all", true).size(), 10u);
  EXPECT_EQ(parse_services("OPEN_DOOR,CLOSE_DOOR", true).size(), 2u);
  EXPECT_THROW(parse_services("OPEN_DOOR,CLOSE_DOOR", false), UsageError);
  EXPECT_THROW(parse_services("all", false), UsageError);
  EXPECT_THROW(parse_services("open_door", true), UsageError);
  EXPECT_EQ(default_interface_type(core::Service::OpenChuck), core::InterfaceType::Chuck);
  EXPECT_EQ(default_interface_type(core::Service::MaterialFeed), core::InterfaceType::BarFeeder);
}

TEST(Services, ActionDurationsRepeatTheLastValue) {
  const auto a = parse_action_ms("60000,10");
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0].count(), 60000);
  EXPECT_THROW(parse_action_ms(","), UsageError);
}

TEST(FailPlan, FixedStepAppliesToListedHandshakesOnly) {
  FailPlan plan(FailStep::Active, {2, 4}, 0.0, 1);
  EXPECT_FALSE(plan.decide(1).fails());
  EXPECT_EQ(plan.decide(2).step, FailStep::Active);
  EXPECT_FALSE(plan.decide(3).fails());
  EXPECT_TRUE(plan.decide(4).fails());
  FailPlan every(FailStep::Accept, {}, 0.0, 1);
  EXPECT_TRUE(every.decide(1).fails());
  EXPECT_TRUE(every.decide(7).fails());
}

TEST(FailPlan, RateIsReproducibleForASeedAndRoughlyRight) {
  FailPlan a(FailStep::None, {}, 0.3, 7);
  FailPlan b(FailStep::None, {}, 0.3, 7);
  int fails = 0;
  std::set<FailStep> steps;
  for (std::uint64_t n = 1; n <= 1000; ++n) {
    const auto da = a.decide(n);
    const auto db = b.decide(n);
    EXPECT_EQ(da.step, db.step);
    if (da.fails()) {
      ++fails;
      steps.insert(da.step);
    }
  }
  EXPECT_GT(fails, 230);
  EXPECT_LT(fails, 370);
  EXPECT_EQ(steps.size(), 3u);  // accept, active and complete all occur
}

TEST(JsonLine, EscapesAndRoundTripsThroughTheTestReader) {
  JsonLine line;
  line.field("event", "outcome")
      .field("handshake", std::uint64_t{12})
      .field("reason", "say \"hi\"\n");
  JsonLine quoted;
  quoted.field("reason", "say \"hi\"");
  const std::string text = line.str();
  EXPECT_EQ(text, "{\"event\":\"outcome\",\"handshake\":12,\"reason\":\"say \\\"hi\\\"\\n\"}");
  EXPECT_EQ(test::json_field(text, "handshake"), "12");
  EXPECT_EQ(test::json_field(quoted.str(), "reason"), "say \"hi\"");
  EXPECT_FALSE(test::json_field(text, "missing"));
}

TEST(Profiles, ParticipantProfilesSelectTheTransportEndpointPresetsAreRefused) {
  CommandSpec spec;
  spec.name = "x";
  add_common_options(spec);
  auto common = parse_common_options(
      parse_args(spec, {"--qos-profile", std::string(qos::kLoopbackUdpParticipantProfile)}));
  EXPECT_EQ(common.profile_transport, qos::Transport::LoopbackUdp);
  common = parse_common_options(parse_args(spec, {}));
  EXPECT_FALSE(common.profile_transport.has_value());
  // The runtime picks endpoint presets itself: naming one selects nothing.
  for (const auto& preset : qos::preset_names()) {
    EXPECT_THROW(parse_common_options(parse_args(spec, {"--qos-profile", preset})), UsageError)
        << preset;
  }
  EXPECT_THROW(parse_common_options(parse_args(spec, {"--qos-profile", "mtc.fast"})), UsageError);
}

// Every command's transport: the network unless --transport or a participant
// profile chooses (issue 10). request and respond parse equipment options,
// watch and list observer options.
TEST(Transport, EveryCommandDefaultsToTheNetwork) {
  CommandSpec equipment;
  equipment.name = "request";
  add_common_options(equipment);
  add_equipment_options(equipment, false);
  const std::vector<std::string> base = {"--device",  "cnc-1",         "--interface",   "mh1",
                                         "--service", "MATERIAL_LOAD", "--counterpart", "robot-1"};
  const auto equipment_transport = [&](std::vector<std::string> extra) {
    extra.insert(extra.begin(), base.begin(), base.end());
    return parse_equipment_options(parse_args(equipment, extra), false, true).transport;
  };
  EXPECT_EQ(equipment_transport({}), qos::Transport::Network);
  EXPECT_EQ(equipment_transport({"--transport", "loopback"}), qos::Transport::Loopback);
  EXPECT_EQ(equipment_transport({"--qos-profile", "mtc.participant.loopback_udp"}),
            qos::Transport::LoopbackUdp);

  CommandSpec observer;
  observer.name = "watch";
  add_common_options(observer);
  add_observer_options(observer);
  const auto observer_transport = [&](const std::vector<std::string>& args) {
    const auto parsed = parse_args(observer, args);
    return parse_observer_options(parsed, parse_common_options(parsed)).transport;
  };
  EXPECT_EQ(observer_transport({}), qos::Transport::Network);
  EXPECT_EQ(observer_transport({"--transport", "loopback"}), qos::Transport::Loopback);
  EXPECT_EQ(EquipmentConfig{}.transport, qos::Transport::Network);
  EXPECT_EQ(ObserverSettings{}.transport, qos::Transport::Network);
}

}  // namespace
}  // namespace mtc::cli
