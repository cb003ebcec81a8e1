// Command-line parsing for the `mtc` tool: each subcommand declares its
// options as data (name, value or switch, help), and one parser handles
// "--name value", "--name=value" and switches for all of them. Bad input is a
// UsageError, which main() turns into a clear message and exit code 2.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace mtc::cli {

// Bad flags, missing values, unknown names: the user's mistake, exit 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct OptionSpec {
  std::string name;        // without the leading "--"
  std::string value_name;  // empty: a switch that takes no value
  std::string help;
  std::string default_text;  // shown in --help; empty = no default shown
  bool hidden = false;       // test-only knobs, left out of --help
  bool repeatable = false;   // may be given more than once
};

struct CommandSpec {
  std::string name;
  std::string summary;      // one line, shown by `mtc --help`
  std::string description;  // paragraph(s) shown by `mtc <name> --help`
  std::vector<OptionSpec> options;
  std::string examples;  // shown last in --help
};

class ParsedArgs {
 public:
  bool has(const std::string& name) const { return values_.count(name) != 0; }
  // Last value given for an option, or nullopt.
  std::optional<std::string> value(const std::string& name) const;
  // Every value given for a repeatable option, in order.
  std::vector<std::string> values(const std::string& name) const;
  std::string value_or(const std::string& name, const std::string& fallback) const;

  void add(const std::string& name, std::string value) {
    values_[name].push_back(std::move(value));
  }

 private:
  std::map<std::string, std::vector<std::string>> values_;
};

// Parses args (without program and subcommand names) against spec. Throws
// UsageError on unknown options, missing values and stray positionals.
ParsedArgs parse_args(const CommandSpec& spec, const std::vector<std::string>& args);

// Help text of one subcommand: usage, description, options, examples.
std::string format_help(const CommandSpec& spec);

// Typed conversions; `option` names the flag in the error message.
std::int64_t to_int(const std::string& option, const std::string& text, std::int64_t min,
                    std::int64_t max);
double to_double(const std::string& option, const std::string& text, double min, double max);
// "250ms", "2s", "1.5s", "1m"; a bare number means seconds.
std::chrono::milliseconds to_duration(const std::string& option, const std::string& text);
// Comma-separated list, empty items removed.
std::vector<std::string> split_list(const std::string& text);

}  // namespace mtc::cli
