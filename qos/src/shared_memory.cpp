#include "mtc/qos/shared_memory.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <mutex>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

namespace mtc::qos {

namespace {

constexpr std::string_view kPrefix = "fastrtps_";
constexpr std::string_view kPort = "port";
constexpr std::string_view kLockSuffix = "_el";
constexpr std::size_t kSegmentIdLength = 16;

enum class Kind { None, Segment, Port };

// "fastrtps_<16 of [0-9a-z]>_el" is a segment's lock, "fastrtps_port<digits>_el"
// a port's; nothing else is touched (data-sharing segments, other prefixes).
Kind classify(std::string_view name) {
  if (name.size() <= kPrefix.size() + kLockSuffix.size()) return Kind::None;
  if (name.substr(0, kPrefix.size()) != kPrefix) return Kind::None;
  if (name.substr(name.size() - kLockSuffix.size()) != kLockSuffix) return Kind::None;
  const auto body = name.substr(kPrefix.size(), name.size() - kPrefix.size() - kLockSuffix.size());
  const auto all = [](std::string_view text, auto pred) {
    for (const char c : text) {
      if (!pred(static_cast<unsigned char>(c))) return false;
    }
    return !text.empty();
  };
  if (body.size() == kSegmentIdLength &&
      all(body, [](unsigned char c) { return std::isdigit(c) != 0 || std::islower(c) != 0; })) {
    return Kind::Segment;
  }
  if (body.substr(0, kPort.size()) == kPort && body.size() <= kPort.size() + 5 &&
      all(body.substr(kPort.size()), [](unsigned char c) { return std::isdigit(c) != 0; })) {
    return Kind::Port;
  }
  return Kind::None;
}

std::vector<std::string> list(const std::string& dir) {
  std::vector<std::string> names;
  DIR* d = ::opendir(dir.c_str());
  if (d == nullptr) return names;
  // Single-threaded use of this DIR stream: readdir is safe here.
  while (const dirent* e = ::readdir(d)) {  // NOLINT(concurrency-mt-unsafe)
    names.emplace_back(e->d_name);
  }
  ::closedir(d);
  return names;
}

std::string path_in(const std::string& dir, std::string_view name) {
  std::string path = dir;
  path += '/';
  path += name;
  return path;
}

// True when nobody holds the lock file's flock: its owner is dead. The lock
// is kept (fd stays open) until the caller has removed the files.
bool owner_dead(const std::string& lock_path, int& fd) {
  fd = ::open(lock_path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  if (::flock(fd, LOCK_EX | LOCK_NB) == 0) return true;
  ::close(fd);
  fd = -1;
  return false;
}

// Removes one lock's files when their owner is dead; false when it is held.
bool remove_if_dead(const std::string& dir, const std::string& name, Kind kind,
                    StaleSharedMemory& out) {
  const std::string lock_path = path_in(dir, name);
  const std::string object = name.substr(0, name.size() - kLockSuffix.size());
  int fd = -1;
  if (!owner_dead(lock_path, fd)) return false;
  // The object first, its lock last (held until then): nobody can take
  // the name over in between.
  ::unlink(path_in(dir, object).c_str());
  if (kind == Kind::Port) ::unlink(path_in(dir, "sem." + object + "_mutex").c_str());
  ::unlink(lock_path.c_str());
  ::close(fd);
  ++(kind == Kind::Segment ? out.segments : out.ports);
  return true;
}

}  // namespace

StaleSharedMemory remove_stale_shared_memory(const std::string& dir,
                                             const std::function<void(int attempt)>& pause) {
  StaleSharedMemory out;
  std::vector<std::pair<std::string, Kind>> held;
  for (const auto& name : list(dir)) {
    const Kind kind = classify(name);
    if (kind != Kind::None && !remove_if_dead(dir, name, kind, out)) held.emplace_back(name, kind);
  }
  for (int attempt = 1; attempt <= kStaleProbeRetries && !held.empty(); ++attempt) {
    if (pause) {
      pause(attempt);
    } else {
      // No event says that another process let go of a lock: a short wait.
      std::this_thread::sleep_for(std::chrono::milliseconds(1 << (attempt - 1)));
    }
    std::vector<std::pair<std::string, Kind>> still;
    for (const auto& [name, kind] : held) {
      if (!remove_if_dead(dir, name, kind, out)) still.emplace_back(name, kind);
    }
    held.swap(still);
  }
  out.in_use = static_cast<int>(held.size());
  return out;
}

void remove_stale_shared_memory_once() {
  static std::once_flag once;
  std::call_once(once, [] { remove_stale_shared_memory(); });
}

}  // namespace mtc::qos
