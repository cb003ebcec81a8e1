// Exit codes of the `mtc` tool, documented in `mtc --help` and the README so
// scripts can tell a failed handshake from a timeout or a usage mistake.
#pragma once

namespace mtc::cli {

enum ExitCode : int {
  kExitOk = 0,            // every handshake COMPLETE / command succeeded
  kExitError = 1,         // runtime error (DDS entity creation, I/O)
  kExitUsage = 2,         // bad flags, unknown service or profile name
  kExitFail = 3,          // a handshake ended in FAIL
  kExitTimeout = 4,       // no outcome (or no counterpart) within --timeout
  kExitCommsLost = 5,     // counterpart lost (liveliness/heartbeat) during a handshake
  kExitNotReady = 6,      // counterpart NOT_READY, request refused
  kExitInterrupted = 130  // stopped by SIGINT/SIGTERM before finishing
};

}  // namespace mtc::cli
