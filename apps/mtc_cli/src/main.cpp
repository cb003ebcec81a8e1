// mtc: command-line tool for MTConnect Part 5 interfaces over DDS.
//   mtc watch | list | request | respond   (mtc <command> --help for each)
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "mtc/dds/error.hpp"

namespace {

using mtc::cli::Command;

std::vector<Command> all_commands() {
  return {mtc::cli::watch_command(), mtc::cli::list_command(), mtc::cli::request_command(),
          mtc::cli::respond_command()};
}

void print_overview(std::ostream& out, const std::vector<Command>& commands) {
  out << "mtc: watch and drive MTConnect Part 5 interfaces (request/response handshakes)\n"
         "carried over DDS.\n\n"
         "Usage: mtc <command> [options]\n\nCommands:\n";
  for (const auto& c : commands) {
    out << "  " << c.spec.name << std::string(10 - c.spec.name.size(), ' ') << c.spec.summary
        << "\n";
  }
  out << "\nEvery command takes --domain N (DDS domain id, default 0), --qos-profile NAME\n"
         "and --json (one JSON object per line). 'mtc <command> --help' shows its options\n"
         "and examples.\n\n"
         "Exit codes: 0 success (COMPLETE), 1 runtime error, 2 usage error, 3 handshake FAIL,\n"
         "4 timeout, 5 counterpart lost, 6 counterpart NOT_READY, 7 excluded (the responder\n"
         "interface is paired with another requester), 130 interrupted.\n\n"
         "Quick start (two terminals):\n"
         "  mtc respond --device machine-1 --interface mh --service MATERIAL_LOAD\n"
         "  mtc request --device robot-1 --interface mh --service MATERIAL_LOAD "
         "--counterpart machine-1\n";
}

int run_command(const Command& command, const std::vector<std::string>& args) {
  for (const auto& a : args) {
    if (a == "--help" || a == "-h") {
      std::cout << mtc::cli::format_help(command.spec);
      return mtc::cli::ExitOk;
    }
  }
  mtc::cli::ParsedArgs parsed;
  try {
    parsed = mtc::cli::parse_args(command.spec, args);
  } catch (const mtc::cli::UsageError& e) {
    std::cerr << "mtc " << command.spec.name << ": error: " << e.what() << "\n"
              << "Try 'mtc " << command.spec.name << " --help'.\n";
    return mtc::cli::ExitUsage;
  }
  // Constructed before any DDS thread exists so that every thread inherits
  // the blocked SIGINT/SIGTERM mask.
  mtc::cli::ShutdownSignal shutdown;
  mtc::cli::Output out(std::cout);
  mtc::cli::Output err(std::cerr);
  mtc::cli::Context context{out, err, shutdown};
  try {
    return command.run(parsed, context);
  } catch (const mtc::cli::UsageError& e) {
    err.line("mtc " + command.spec.name + ": error: " + e.what() + "\nTry 'mtc " +
             command.spec.name + " --help'.");
    return mtc::cli::ExitUsage;
  } catch (const mtc::dds::ConfigError& e) {
    // Bad device uuid / interface id and the like: the user's input.
    err.line("mtc " + command.spec.name + ": error: " + e.what());
    return mtc::cli::ExitUsage;
  } catch (const std::exception& e) {
    err.line("mtc " + command.spec.name + ": " + e.what());
    return mtc::cli::ExitError;
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<Command> commands = all_commands();
  if (argc < 2) {
    print_overview(std::cerr, commands);
    return mtc::cli::ExitUsage;
  }
  const std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help") {
    print_overview(std::cout, commands);
    return mtc::cli::ExitOk;
  }
  for (const auto& c : commands) {
    if (c.spec.name == name) {
      return run_command(c, std::vector<std::string>(argv + 2, argv + argc));
    }
  }
  std::cerr << "mtc: unknown command '" << name << "'\nTry 'mtc --help'.\n";
  return mtc::cli::ExitUsage;
}
