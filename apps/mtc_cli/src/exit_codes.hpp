// Exit codes of the `mtc` tool, documented in `mtc --help` and docs/cli.md so
// scripts can tell a failed handshake from a timeout or a usage mistake.
#pragma once

namespace mtc::cli {

enum ExitCode : int {
  ExitOk = 0,            // every handshake COMPLETE / command succeeded
  ExitError = 1,         // runtime error (DDS entity creation, I/O)
  ExitUsage = 2,         // bad flags, unknown service or profile name
  ExitFail = 3,          // a handshake ended in FAIL
  ExitTimeout = 4,       // no outcome (or no counterpart) within --timeout
  ExitCommsLost = 5,     // counterpart lost (liveliness/heartbeat) during a handshake
  ExitNotReady = 6,      // counterpart NOT_READY, request refused
  ExitExcluded = 7,      // the responder interface is paired with another requester
  ExitInterrupted = 130  // stopped by SIGINT/SIGTERM before finishing
};

}  // namespace mtc::cli
