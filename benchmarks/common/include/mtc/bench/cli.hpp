// Command line of the benchmark executables: one small parser, so that every
// benchmark answers --help (usage on stdout, exit 0) and rejects an unknown
// option or a bad value (one error line and the usage on stderr, exit 2)
// before it starts anything. Options bind to variables whose initial values
// are the defaults the usage prints, so the text cannot drift from the code.
//
//   int samples = 2000;
//   mtc::bench::Cli cli("mtc-bench-x", "What it measures; where the JSON goes.");
//   cli.integer("--samples", samples, 1, 1000000, "samples to take");
//   if (const auto exit_code = cli.parse(argc, argv)) return *exit_code;
#pragma once

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace mtc::bench {

inline constexpr int kExitOk = 0;
inline constexpr int kExitUsage = 2;

class Cli {
 public:
  // `about`: what the benchmark measures and where its output (JSON) goes.
  Cli(std::string program, std::string about)
      : program_(std::move(program)), about_(std::move(about)) {}

  // --name N, an integer in [min, max].
  Cli& integer(const std::string& name, int& value, int min, int max, const std::string& help) {
    const std::string range = std::to_string(min) + "-" + std::to_string(max);
    add(name, "N", help, "default " + std::to_string(value) + ", range " + range,
        [&value, min, max, name, range](const std::string& text) {
          errno = 0;
          char* end = nullptr;
          const long parsed = std::strtol(text.c_str(), &end, 10);
          const bool digits =
              !text.empty() && (std::isdigit(static_cast<unsigned char>(text[0])) != 0 ||
                                text[0] == '-' || text[0] == '+');
          if (!digits || *end != '\0' || errno == ERANGE || parsed < min || parsed > max) {
            return std::optional<std::string>(name + " expects an integer in " + range + ", got '" +
                                              text + "'");
          }
          value = static_cast<int>(parsed);
          return std::optional<std::string>();
        });
    return *this;
  }

  // --name VALUE, any non-empty text (`value_name` names it in the usage).
  Cli& text(const std::string& name, const std::string& value_name, std::string& value,
            const std::string& help) {
    add(name, value_name, help, value.empty() ? "" : "default " + value,
        [&value, name](const std::string& text) {
          if (text.empty()) {
            return std::optional<std::string>(name + " expects a non-empty value");
          }
          value = text;
          return std::optional<std::string>();
        });
    return *this;
  }

  // --name VALUE, one of `choices`.
  Cli& choice(const std::string& name, std::string& value, const std::vector<std::string>& choices,
              const std::string& help) {
    std::string names;
    for (const auto& c : choices) {
      names += (names.empty() ? "" : "|") + c;
    }
    add(name, names, help, value.empty() ? "" : "default " + value,
        [&value, name, choices, names](const std::string& text) {
          if (std::find(choices.begin(), choices.end(), text) == choices.end()) {
            return std::optional<std::string>(name + " expects " + names + ", got '" + text + "'");
          }
          value = text;
          return std::optional<std::string>();
        });
    return *this;
  }

  // --name without a value: sets `value` to true.
  Cli& flag(const std::string& name, bool& value, const std::string& help) {
    add(name, "", help, "", [&value](const std::string&) {
      value = true;
      return std::optional<std::string>();
    });
    return *this;
  }

  // Options declared after this call are set by the benchmark itself for the
  // processes it starts; the usage lists them apart.
  Cli& internal_options_follow() {
    internal_ = true;
    return *this;
  }

  // nullopt: the command line is good, go on with the run. Otherwise the
  // exit code for main() to return: 0 after --help, 2 after a usage error
  // (both already reported).
  std::optional<int> parse(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--help" || a == "-h") {
        print_usage(std::cout);
        return kExitOk;
      }
    }
    for (int i = 1; i < argc; ++i) {
      if (const auto error = parse_one(argc, argv, i)) {
        return usage_error(*error);
      }
    }
    return std::nullopt;
  }

  // For checks across options after parse(): reports and returns 2.
  int usage_error(const std::string& message) const {
    std::cerr << program_ << ": " << message << "\n\n";
    print_usage(std::cerr);
    return kExitUsage;
  }

  void print_usage(std::ostream& out) const {
    out << "usage: " << program_ << " [options]\n\n" << about_ << "\n\nOptions:\n";
    for (const auto& o : options_) {
      if (!o.internal) {
        print_option(out, o);
      }
    }
    print_line(out, "-h, --help", "show this text and exit");
    const bool any_internal =
        std::any_of(options_.begin(), options_.end(), [](const Option& o) { return o.internal; });
    if (any_internal) {
      out << "\nInternal options (the benchmark passes them to the processes it starts):\n";
      for (const auto& o : options_) {
        if (o.internal) {
          print_option(out, o);
        }
      }
    }
  }

 private:
  using Setter = std::function<std::optional<std::string>(const std::string&)>;

  struct Option {
    std::string name;        // "--samples"
    std::string value_name;  // "N"; empty for a flag
    std::string help;
    std::string notes;  // "default 10, range 1-3600", shown after the help
    bool internal = false;
    bool seen = false;
    Setter set;
  };

  void add(const std::string& name, const std::string& value_name, const std::string& help,
           const std::string& notes, Setter set) {
    options_.push_back({name, value_name, help, notes, internal_, false, std::move(set)});
  }

  // Parses argv[i] ("--name value" or "--name=value"), advancing i past a
  // value. Returns an error message.
  std::optional<std::string> parse_one(int argc, char** argv, int& i) {
    std::string name = argv[i];
    std::optional<std::string> inline_value;
    if (const auto eq = name.find('='); name.rfind("--", 0) == 0 && eq != std::string::npos) {
      inline_value = name.substr(eq + 1);
      name.resize(eq);
    }
    const auto it = std::find_if(options_.begin(), options_.end(),
                                 [&](const Option& o) { return o.name == name; });
    if (it == options_.end()) {
      return name.rfind('-', 0) == 0 ? "unknown option '" + name + "'"
                                     : "unexpected argument '" + name + "'";
    }
    if (it->seen) {
      return "option '" + name + "' given more than once";
    }
    it->seen = true;
    if (it->value_name.empty()) {
      return inline_value ? "option '" + name + "' takes no value" : it->set("");
    }
    if (!inline_value) {
      if (i + 1 >= argc) {
        return "option '" + name + "' needs a value (" + it->value_name + ")";
      }
      inline_value = argv[++i];
    }
    return it->set(*inline_value);
  }

  // The notes go after the help, or on a line of their own where the line
  // would grow past kWidth.
  static void print_option(std::ostream& out, const Option& o) {
    std::string help = o.help;
    if (!o.notes.empty()) {
      const std::size_t last_line = help.size() - (help.rfind('\n') + 1);
      const bool fits = kColumn + last_line + o.notes.size() + 3 <= kWidth;
      help += (fits ? " (" : "\n(") + o.notes + ")";
    }
    print_line(out, o.value_name.empty() ? o.name : o.name + " " + o.value_name, help);
  }

  // "  --name VALUE   help", the help in a column; lines of `help` after the
  // first (split on '\n') and help that does not fit beside a long name go
  // below, indented to that column.
  static void print_line(std::ostream& out, const std::string& left, const std::string& help) {
    out << "  " << left;
    std::size_t used = 2 + left.size();
    std::istringstream lines(help);
    std::string line;
    while (std::getline(lines, line)) {
      if (used + 2 > kColumn) {
        out << "\n";
        used = 0;
      }
      out << std::string(kColumn - used, ' ') << line << "\n";
      used = 0;
    }
  }

  static constexpr std::size_t kColumn = 26;  // where the help starts
  static constexpr std::size_t kWidth = 90;

  std::string program_;
  std::string about_;
  std::vector<Option> options_;
  bool internal_ = false;
};

}  // namespace mtc::bench
