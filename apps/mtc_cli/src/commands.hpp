// The subcommands of the `mtc` tool. Each one is a CommandSpec (its options
// and help, as data) plus a run function; main() parses the arguments,
// handles --help and usage errors, and calls run with a Context.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cli_args.hpp"
#include "mtc/qos/participant.hpp"
#include "output.hpp"
#include "shutdown_signal.hpp"

namespace mtc::cli {

struct Context {
  Output& out;  // stdout, one flushed line per event
  Output& err;  // stderr, diagnostics
  ShutdownSignal& shutdown;
};

// Options every subcommand shares.
struct CommonOptions {
  int domain = 0;
  // Set by --qos-profile, a participant profile
  // ("mtc.participant.loopback_udp"): the transport it selects. Endpoint QoS
  // is not selectable (each topic's preset follows from the heartbeat).
  std::optional<qos::Transport> profile_transport;
  bool json = false;
  // --security DIR: the DDS-Security identity (scripts/security/make-pki.sh).
  std::string security_dir;
};

void add_common_options(CommandSpec& spec);
// Throws UsageError for an out-of-range domain or an unknown profile name.
CommonOptions parse_common_options(const ParsedArgs& args);

struct Command {
  CommandSpec spec;
  int (*run)(const ParsedArgs& args, Context& context) = nullptr;
};

Command watch_command();
Command list_command();
Command request_command();
Command respond_command();

}  // namespace mtc::cli
