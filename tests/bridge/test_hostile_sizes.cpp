// Requests and options that would make the agent allocate without bound:
// a /sample of the whole buffer is capped at max_document_bytes and pages
// on by nextSequence; a buffer beyond kMaxBufferSize is refused by name.
#include <gtest/gtest.h>

#include "bridge_test_util.hpp"

namespace mtc::bridge {
namespace {

using test::Doc;
using test::value;

constexpr std::int64_t kT0 = 1'700'000'000'000'000'000;

std::unique_ptr<MtconnectAgent> full_agent(std::size_t max_document_bytes) {
  AgentOptions o = test::cell_options(SchemaVersion::V1_6, 4096);
  o.max_document_bytes = max_document_bytes;
  auto agent = make_agent(o);
  agent->add_device(test::mill());
  for (int i = 0; i < 5000; ++i) {
    agent->add_value(value(
        "mill-0001", "mill.open_door.rsp",
        i % 2 != 0 ? core::InteractionState::Active : core::InteractionState::Ready, kT0 + i));
  }
  return agent;
}

TEST(HostileSize, ASampleOfTheWholeBufferStopsAtTheCapAndPagesOn) {
  auto agent = full_agent(std::size_t{64} << 10);
  const Response r = test::get(*agent, "/sample?count=4096");
  ASSERT_EQ(r.status, 200);
  EXPECT_LE(r.body.size(), std::size_t{64} << 10);
  Doc d(r.body);
  ASSERT_TRUE(d.ok);
  const std::size_t got = d.count("//OpenDoor");
  EXPECT_GT(got, 100U);
  EXPECT_LT(got, 4096U);
  // nextSequence is the first observation left out: paging on from it
  // continues without a gap or a repeat.
  const std::uint64_t next = d.number("//Header/@nextSequence");
  const std::uint64_t last = d.number("(//OpenDoor)[last()]/@sequence");
  EXPECT_EQ(next, last + 1);
  Doc page(test::get(*agent, "/sample?count=4096&from=" + std::to_string(next)).body);
  EXPECT_EQ(page.number("(//OpenDoor)[1]/@sequence"), next);
  // The last |count|: the newest that fit, up to nextSequence of the buffer.
  Doc newest(test::get(*agent, "/sample?count=-4096").body);
  EXPECT_EQ(newest.number("(//OpenDoor)[last()]/@sequence") + 1, agent->next_sequence());
  EXPECT_LT(newest.count("//OpenDoor"), 4096U);
}

TEST(HostileSize, UncappedTheSameSampleIsWhole) {
  auto agent = full_agent(std::size_t{64} << 20);
  Doc d(test::get(*agent, "/sample?count=4096").body);
  EXPECT_EQ(d.count("//OpenDoor"), 4096U);
}

TEST(HostileSize, ABufferBeyondTheLimitIsRefusedByName) {
  AgentOptions o = test::cell_options();
  o.buffer_size = kMaxBufferSize + 1;
  try {
    (void)make_agent(o);
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("buffer_size must be from 2 to 16777216"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace mtc::bridge
