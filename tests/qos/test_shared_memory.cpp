// qos::remove_stale_shared_memory (issue 10): in a directory laid out as
// Fast DDS lays out /dev/shm, the files whose lock nobody holds (a dead
// owner) go, the files whose lock is held (a live owner) stay, and nothing
// else is touched. A private directory, no DDS.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "mtc/qos/shared_memory.hpp"

namespace {

namespace fs = std::filesystem;

class StaleSharedMemory : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "mtc-shm-XXXXXX").string();
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
  }
  void TearDown() override {
    if (held_ >= 0) ::close(held_);
    fs::remove_all(dir_);
  }
  void touch(const std::string& name) const { std::ofstream(dir_ / name) << "x"; }
  bool exists(const std::string& name) const { return fs::exists(dir_ / name); }
  // Holds a lock file as its live owner does (flock, kept while the test runs).
  void hold(const std::string& name) {
    touch(name);
    held_ = ::open((dir_ / name).c_str(), O_RDONLY | O_CLOEXEC);
    ASSERT_GE(held_, 0);
    ASSERT_EQ(::flock(held_, LOCK_EX | LOCK_NB), 0);
  }

  fs::path dir_;
  int held_ = -1;
};

TEST_F(StaleSharedMemory, RemovesTheDeadAndLeavesTheLiveAndTheRest) {
  // A dead process's segment and port (nobody holds their locks).
  touch("fastrtps_0123456789abcdef");
  touch("fastrtps_0123456789abcdef_el");
  touch("fastrtps_port7413");
  touch("fastrtps_port7413_el");
  touch("sem.fastrtps_port7413_mutex");
  // A live process's segment.
  touch("fastrtps_fedcba9876543210");
  hold("fastrtps_fedcba9876543210_el");
  // Not Fast DDS segment or port locks: left alone.
  touch("fast_datasharing_0123456789abcdef_el");
  touch("fastrtps_short_el");
  touch("other_el");

  const auto removed = mtc::qos::remove_stale_shared_memory(dir_.string());
  EXPECT_EQ(removed.segments, 1);
  EXPECT_EQ(removed.ports, 1);
  EXPECT_EQ(removed.in_use, 1);
  for (const char* gone :
       {"fastrtps_0123456789abcdef", "fastrtps_0123456789abcdef_el", "fastrtps_port7413",
        "fastrtps_port7413_el", "sem.fastrtps_port7413_mutex"}) {
    EXPECT_FALSE(exists(gone)) << gone;
  }
  for (const char* kept :
       {"fastrtps_fedcba9876543210", "fastrtps_fedcba9876543210_el",
        "fast_datasharing_0123456789abcdef_el", "fastrtps_short_el", "other_el"}) {
    EXPECT_TRUE(exists(kept)) << kept;
  }
}

// A live process probing a dead peer's port (Fast DDS's zombie check) holds
// its lock for a moment: a lock held at the first probe and let go before
// the next one is a dead owner's after all, and its files go.
TEST_F(StaleSharedMemory, ALockHeldForAMomentIsProbedAgain) {
  touch("fastrtps_port7415");
  hold("fastrtps_port7415_el");
  std::vector<int> pauses;
  const auto removed = mtc::qos::remove_stale_shared_memory(dir_.string(), [&](int attempt) {
    pauses.push_back(attempt);
    if (attempt == 1) {
      ::close(held_);  // the prober lets go
      held_ = -1;
    }
  });
  EXPECT_EQ(removed.ports, 1);
  EXPECT_EQ(removed.in_use, 0);
  EXPECT_EQ(pauses, std::vector<int>{1});
  EXPECT_FALSE(exists("fastrtps_port7415_el"));
  EXPECT_FALSE(exists("fastrtps_port7415"));
}

// A lock held throughout is a live owner's: probed again a bounded number
// of times, then left alone.
TEST_F(StaleSharedMemory, ALockHeldThroughoutIsLeftAfterBoundedRetries) {
  touch("fastrtps_fedcba9876543210");
  hold("fastrtps_fedcba9876543210_el");
  int pauses = 0;
  const auto removed = mtc::qos::remove_stale_shared_memory(dir_.string(), [&](int) { ++pauses; });
  EXPECT_EQ(removed.in_use, 1);
  EXPECT_EQ(pauses, mtc::qos::kStaleProbeRetries);
  EXPECT_TRUE(exists("fastrtps_fedcba9876543210_el"));
}

TEST_F(StaleSharedMemory, AMissingDirectoryIsNoError) {
  const auto removed = mtc::qos::remove_stale_shared_memory((dir_ / "absent").string());
  EXPECT_EQ(removed.segments + removed.ports + removed.in_use, 0);
}

}  // namespace
