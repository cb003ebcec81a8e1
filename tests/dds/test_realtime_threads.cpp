// Fast DDS's own threads (receive, event, SHM listener) inherit SCHED_FIFO
// priority 1 from the thread that creates the participant, when the process
// may have it (root in CI; see dds/src/entities.cpp for why), and the
// creating thread gets its own policy back. MTC_NO_REALTIME=1 opts out.
// Domain 199 (a participant alone; nothing to discover).
#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>
#include <sys/types.h>

#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>

#include "mtc/dds/detail/entities.hpp"
#include "mtc/qos/participant.hpp"
#include "transport.hpp"

namespace mtc::dds::detail {
namespace {

constexpr int kDomain = 199;

std::set<pid_t> thread_ids() {
  std::set<pid_t> ids;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/task")) {
    ids.insert(static_cast<pid_t>(std::stol(entry.path().filename().string())));
  }
  return ids;
}

// Whether this process may raise a thread to SCHED_FIFO at all.
bool realtime_permitted() {
  int policy = 0;
  sched_param before{};
  if (pthread_getschedparam(pthread_self(), &policy, &before) != 0) return false;
  sched_param realtime{};
  realtime.sched_priority = 1;
  if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &realtime) != 0) return false;
  pthread_setschedparam(pthread_self(), policy, &before);
  return true;
}

// Policies of the threads the participant started.
std::multiset<int> new_thread_policies(const std::set<pid_t>& before) {
  std::multiset<int> policies;
  for (const pid_t id : thread_ids()) {
    if (before.count(id) == 0) policies.insert(sched_getscheduler(id));
  }
  return policies;
}

qos::ParticipantConfig loopback_config() {
  auto config = test::loopback<qos::ParticipantConfig>();
  config.name = "realtime-threads";
  return config;
}

TEST(RealtimeThreads, ParticipantThreadsInheritRealtimeWhenPermittedAndTheCallerKeepsItsPolicy) {
  ::unsetenv("MTC_NO_REALTIME");
  // Without the privilege (a non-root user namespace) nothing may change.
  const int expected = realtime_permitted() ? SCHED_FIFO : SCHED_OTHER;
  const auto before = thread_ids();
  Participant participant(kDomain, checked_qos(loopback_config()));
  const auto policies = new_thread_policies(before);
  ASSERT_FALSE(policies.empty());
  EXPECT_EQ(policies.count(expected), policies.size())
      << "every new thread has policy " << expected;
  EXPECT_EQ(sched_getscheduler(0), SCHED_OTHER) << "the creating thread is back to normal";
}

TEST(RealtimeThreads, OptOutLeavesEveryThreadNormal) {
  ::setenv("MTC_NO_REALTIME", "1", 1);
  const auto before = thread_ids();
  {
    Participant participant(kDomain, checked_qos(loopback_config()));
    const auto policies = new_thread_policies(before);
    ASSERT_FALSE(policies.empty());
    EXPECT_EQ(policies.count(SCHED_OTHER), policies.size());
  }
  ::unsetenv("MTC_NO_REALTIME");
}

}  // namespace
}  // namespace mtc::dds::detail
