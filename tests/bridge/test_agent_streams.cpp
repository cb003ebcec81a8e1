// Streaming requests: route() returns a StreamPlan, next_part() walks the
// buffer chunk by chunk, wait_for()/subscribe() wake streams on new data.
#include <gtest/gtest.h>

#include <future>
#include <thread>

#include "bridge_test_util.hpp"

namespace mtc::bridge {
namespace {

using test::Doc;
using test::value;

constexpr std::int64_t kT0 = 1'700'000'000'000'000'000;

TEST(AgentStreams, IntervalRequestsBecomeStreamPlans) {
  auto agent = test::announced_cell();
  const Routed r = agent->route("GET", "/mill/sample?interval=250&heartbeat=2000&count=5");
  ASSERT_TRUE(r.stream.has_value());
  EXPECT_FALSE(r.response.has_value());
  EXPECT_TRUE(r.stream->is_sample);
  EXPECT_EQ(r.stream->interval.count(), 250);
  EXPECT_EQ(r.stream->heartbeat.count(), 2000);
  // The parameters are typed once, for every part.
  EXPECT_EQ(r.stream->parameters.device, "mill");
  EXPECT_EQ(r.stream->parameters.count, 5);
  const Routed c = agent->route("GET", "/current?interval=0");
  ASSERT_TRUE(c.stream.has_value());
  EXPECT_FALSE(c.stream->is_sample);
  EXPECT_EQ(c.stream->heartbeat.count(), 10000);
}

TEST(AgentStreams, PartsWalkTheBufferInCountSizedChunks) {
  auto agent = test::announced_cell();
  const std::uint64_t start = agent->next_sequence();
  for (int i = 0; i < 7; ++i) {
    agent->add_value(value(
        "mill-0001", "mill.material_load.req",
        i % 2 != 0 ? core::InteractionState::Active : core::InteractionState::Ready, kT0 + i));
  }
  Routed r = agent->route("GET", "/sample?interval=10&count=3&from=" + std::to_string(start) +
                                     "&path=//DataItem[@type='MATERIAL_LOAD']");
  ASSERT_TRUE(r.stream);
  StreamPlan plan = *r.stream;
  std::vector<std::uint64_t> seen;
  for (int part = 0; part < 3; ++part) {
    const Response p = agent->next_part(plan);
    ASSERT_EQ(p.status, 200);
    Doc d(p.body);
    for (const auto& n : d.xml.select_nodes("//MaterialLoad")) {
      seen.push_back(n.node().attribute("sequence").as_ullong());
    }
    EXPECT_EQ(d.number("//Header/@nextSequence"), plan.next_sequence);
  }
  ASSERT_EQ(seen.size(), 7u);
  for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], start + i);
  // Nothing new: an empty (heartbeat) document, with no DeviceStream as
  // from the reference agent.
  const Response idle = agent->next_part(plan);
  EXPECT_EQ(idle.status, 200);
  Doc d(idle.body);
  EXPECT_EQ(d.count("//MaterialLoad"), 0u);
  EXPECT_EQ(d.count("/MTConnectStreams/Streams"), 1u);
  EXPECT_EQ(d.count("/MTConnectStreams/Streams/DeviceStream"), 0u);
  EXPECT_EQ(plan.next_sequence, agent->next_sequence());
}

TEST(AgentStreams, StreamThatFellBehindGetsOutOfRange) {
  auto agent = test::announced_cell(SchemaVersion::V1_6, 8);
  Routed r = agent->route("GET", "/sample?interval=10");
  ASSERT_TRUE(r.stream);
  StreamPlan plan = *r.stream;
  for (int i = 0; i < 30; ++i) {
    agent->add_value(value(
        "mill-0001", "mill.material_load.req",
        i % 2 != 0 ? core::InteractionState::Active : core::InteractionState::Ready, kT0 + i));
  }
  const Response p = agent->next_part(plan);
  EXPECT_EQ(p.status, 400);
  EXPECT_EQ(Doc(p.body).text("//Error/@errorCode"), "OUT_OF_RANGE");
}

TEST(AgentStreams, CurrentStreamPartsAreCurrentDocuments) {
  auto agent = test::announced_cell();
  Routed r = agent->route("GET", "/robot/current?interval=100");
  ASSERT_TRUE(r.stream);
  StreamPlan plan = *r.stream;
  agent->add_value(value("robot-0001", "robot.mh.state", core::InterfaceState::Enabled, kT0));
  const Response p = agent->next_part(plan);
  Doc d(p.body);
  EXPECT_EQ(d.text("//InterfaceState"), "ENABLED");
  EXPECT_EQ(d.count("//DeviceStream"), 1u);
}

TEST(AgentStreams, WaitForWakesOnNewData) {
  auto agent = test::announced_cell();
  const std::uint64_t next = agent->next_sequence();
  EXPECT_TRUE(agent->wait_for(next - 1, std::chrono::milliseconds(0)));
  EXPECT_FALSE(agent->wait_for(next, std::chrono::milliseconds(1)));
  std::promise<void> notified;
  const std::uint64_t id = agent->subscribe([&] { notified.set_value(); });
  auto waiter = std::async(std::launch::async,
                           [&] { return agent->wait_for(next, std::chrono::seconds(30)); });
  agent->add_value(value("mill-0001", "mill.mh.state", core::InterfaceState::Enabled, kT0));
  EXPECT_TRUE(waiter.get());
  EXPECT_EQ(notified.get_future().wait_for(std::chrono::seconds(30)), std::future_status::ready);
  agent->unsubscribe(id);
  // A duplicate adds nothing and notifies nobody.
  agent->add_value(value("mill-0001", "mill.mh.state", core::InterfaceState::Enabled, kT0,
                         /*redelivered=*/true));
  EXPECT_EQ(agent->next_sequence(), next + 1);
}

TEST(AgentStreams, ConcurrentProducersAndReaders) {
  auto agent = test::announced_cell(SchemaVersion::V1_6, 256);
  std::atomic<bool> stop{false};
  std::vector<std::thread> readers;
  std::atomic<int> bad{0};
  readers.reserve(3);
  for (int t = 0; t < 3; ++t) {
    readers.emplace_back([&] {
      while (!stop) {
        for (const char* target :
             {"/current", "/sample?count=50", "/mill/current?path=//DoorInterface"}) {
          const Response r = test::get(*agent, target);
          if (r.status != 200 || !Doc(r.body).ok) ++bad;
        }
      }
    });
  }
  for (int i = 0; i < 5000; ++i) {
    agent->add_value(value(
        "mill-0001", "mill.open_door.rsp",
        i % 2 != 0 ? core::InteractionState::Active : core::InteractionState::Ready, kT0 + i));
  }
  stop = true;
  for (auto& t : readers) t.join();
  EXPECT_EQ(bad.load(), 0);
}

}  // namespace
}  // namespace mtc::bridge
