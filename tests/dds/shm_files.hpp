// Which of Fast DDS's shared-memory files in /dev/shm a process owns: the
// lock files ("<name>_el") it holds with flock(), as /proc/locks lists them
// (pid and inode), and the segment or port each one guards. Read while the
// process is alive (stopped will do), checked again after it died.
#pragma once

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace mtc::dds::testing {

inline constexpr const char* kShmDir = "/dev/shm";

struct ShmFiles {
  std::vector<std::string> segment_locks;  // "fastrtps_<id>_el"
  std::vector<std::string> port_locks;     // "fastrtps_port<N>_el"
};

// The inodes of every flock() that `pid` holds.
inline std::set<std::uint64_t> flocked_inodes(pid_t pid) {
  std::set<std::uint64_t> inodes;
  std::ifstream locks("/proc/locks");
  std::string line;
  while (std::getline(locks, line)) {
    // "1: FLOCK  ADVISORY  WRITE 1234 00:1a:5678 0 EOF"
    std::istringstream in(line);
    std::string id;
    std::string type;
    std::string mode;
    std::string access;
    long owner = 0;
    std::string device_inode;
    if (!(in >> id >> type >> mode >> access >> owner >> device_inode)) continue;
    if (type != "FLOCK" || owner != pid) continue;
    const auto colon = device_inode.rfind(':');
    if (colon == std::string::npos) continue;
    inodes.insert(std::stoull(device_inode.substr(colon + 1)));
  }
  return inodes;
}

inline bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// The shared-memory lock files in /dev/shm that `pid` holds.
inline ShmFiles shm_files_of(pid_t pid) {
  ShmFiles out;
  const auto inodes = flocked_inodes(pid);
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(kShmDir, ec)) {
    const auto name = entry.path().filename().string();
    if (name.rfind("fastrtps_", 0) != 0 || !ends_with(name, "_el")) continue;
    struct stat st {};
    if (::stat((std::string(kShmDir) + "/" + name).c_str(), &st) != 0) continue;
    if (inodes.count(st.st_ino) == 0) continue;
    (name.rfind("fastrtps_port", 0) == 0 ? out.port_locks : out.segment_locks).push_back(name);
  }
  return out;
}

inline bool shm_exists(const std::string& name) {
  return ::access((std::string(kShmDir) + "/" + name).c_str(), F_OK) == 0;
}

// True when some live process holds the lock file (probe: a non-blocking
// exclusive flock that fails).
inline bool shm_lock_held(const std::string& lock_name) {
  const int fd = ::open((std::string(kShmDir) + "/" + lock_name).c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool held = ::flock(fd, LOCK_EX | LOCK_NB) != 0;
  ::close(fd);
  return held;
}

// What of a dead process's files is still there: its segments (which
// nobody else ever opens under that name) must be gone; a port may have
// been opened again by a live process under the same number, but must not
// be left unowned.
inline std::vector<std::string> leftovers(const ShmFiles& dead) {
  std::vector<std::string> left;
  for (const auto& lock : dead.segment_locks) {
    const auto segment = lock.substr(0, lock.size() - 3);
    if (shm_exists(lock)) left.push_back(lock);
    if (shm_exists(segment)) left.push_back(segment);
  }
  for (const auto& lock : dead.port_locks) {
    if (shm_exists(lock) && !shm_lock_held(lock)) left.push_back(lock + " (unowned)");
  }
  return left;
}

}  // namespace mtc::dds::testing
