// Fast DDS's shared-memory files of dead processes (issue 10). A participant
// with the shared-memory transport (Transport::Loopback, Transport::Network)
// creates, in /dev/shm, a segment per participant ("fastrtps_<16 chars>")
// and a port per listening locator ("fastrtps_port<N>", with a named mutex
// "sem.fastrtps_port<N>_mutex"), each guarded by a lock file ("<name>_el")
// that its owner holds with flock() for as long as it lives. A clean exit
// removes them; a SIGKILL or a crash leaves them behind for good (Fast DDS
// 2.9 reuses a dead port when it opens the same port number again, and
// never looks at a dead segment again), which is what `fastdds shm clean`
// (package fastdds-tools) exists for.
//
// remove_stale_shared_memory() does the same from inside the runtime: a
// file guarded by a lock that nobody holds belongs to a dead process and is
// removed; one whose lock is held is a live process's and is left alone. It
// probes each lock with a non-blocking flock() held only while it removes
// the files (a creator that meets the probe picks another segment name; a
// listener that meets it on a port retries when it opens the port again).
// The runtime calls it once per process, before its first participant with
// the shared-memory transport (dds::detail::Participant).
#pragma once

#include <functional>
#include <string>

namespace mtc::qos {

struct StaleSharedMemory {
  int segments = 0;  // dead segments removed (segment + lock file)
  int ports = 0;     // dead ports removed (port + lock file + mutex)
  int in_use = 0;    // lock files held by live processes, left alone
};

// Removes the shared-memory files of dead Fast DDS processes from `dir`
// (default: where Fast DDS puts them on Linux). Never throws; a file it
// cannot open or remove (another user's) is skipped. A lock found held is
// probed again up to kStaleProbeRetries times, after `pause(attempt)`
// (default: 1, 2, 4 ms): a live Fast DDS process holds a dead peer's port
// lock for a moment whenever it checks whether that port is a zombie, which
// it does while it still sends to the dead peer; a single probe that meets
// that moment would leave the dead port behind for good.
inline constexpr int kStaleProbeRetries = 3;
StaleSharedMemory remove_stale_shared_memory(const std::string& dir = "/dev/shm",
                                             const std::function<void(int attempt)>& pause = {});

// Once per process: remove_stale_shared_memory() on the first call, nothing
// after it (a process's own participants are alive).
void remove_stale_shared_memory_once();

}  // namespace mtc::qos
