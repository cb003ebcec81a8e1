#include "cli_args.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace mtc::cli {

std::optional<std::string> ParsedArgs::value(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end() || it->second.empty()) {
    return std::nullopt;
  }
  return it->second.back();
}

std::vector<std::string> ParsedArgs::values(const std::string& name) const {
  auto it = values_.find(name);
  return it == values_.end() ? std::vector<std::string>{} : it->second;
}

std::string ParsedArgs::value_or(const std::string& name, const std::string& fallback) const {
  auto v = value(name);
  return v ? *v : fallback;
}

namespace {

const OptionSpec* find_option(const CommandSpec& spec, const std::string& name) {
  for (const auto& opt : spec.options) {
    if (opt.name == name) {
      return &opt;
    }
  }
  return nullptr;
}

}  // namespace

ParsedArgs parse_args(const CommandSpec& spec, const std::vector<std::string>& args) {
  ParsedArgs parsed;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg.size() < 3 || arg.compare(0, 2, "--") != 0) {
      throw UsageError("unexpected argument '" + arg + "' (options start with --)");
    }
    std::string name = arg.substr(2);
    std::optional<std::string> inline_value;
    if (auto eq = name.find('='); eq != std::string::npos) {
      inline_value = name.substr(eq + 1);
      name.resize(eq);
    }
    const OptionSpec* opt = find_option(spec, name);
    if (opt == nullptr) {
      throw UsageError("unknown option '--" + name + "'");
    }
    if (opt->value_name.empty()) {
      if (inline_value) {
        throw UsageError("option '--" + name + "' takes no value");
      }
      parsed.add(name, "");
      continue;
    }
    if (!opt->repeatable && parsed.has(name)) {
      throw UsageError("option '--" + name + "' given more than once");
    }
    if (inline_value) {
      parsed.add(name, *inline_value);
    } else if (i + 1 < args.size()) {
      parsed.add(name, args[++i]);
    } else {
      throw UsageError("option '--" + name + "' needs a value (" + opt->value_name + ")");
    }
  }
  return parsed;
}

std::string format_help(const CommandSpec& spec) {
  std::ostringstream out;
  out << "Usage: mtc " << spec.name << " [options]\n\n" << spec.description << "\n\nOptions:\n";
  for (const auto& opt : spec.options) {
    if (opt.hidden) {
      continue;
    }
    std::string left = "  --" + opt.name;
    if (!opt.value_name.empty()) {
      left += " " + opt.value_name;
    }
    out << left;
    const std::size_t column = 30;
    if (left.size() + 2 > column) {
      out << "\n" << std::string(column, ' ');
    } else {
      out << std::string(column - left.size(), ' ');
    }
    out << opt.help;
    if (!opt.default_text.empty()) {
      out << " [default: " << opt.default_text << "]";
    }
    out << "\n";
  }
  out << "  --help                      show this help and exit\n";
  if (!spec.examples.empty()) {
    out << "\nExamples:\n" << spec.examples;
  }
  return out.str();
}

std::int64_t to_int(const std::string& option, const std::string& text, std::int64_t min,
                    std::int64_t max) {
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || v < min || v > max) {
    throw UsageError("--" + option + " expects an integer in [" + std::to_string(min) + ", " +
                     std::to_string(max) + "], got '" + text + "'");
  }
  return v;
}

double to_double(const std::string& option, const std::string& text, double min, double max) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v) || v < min ||
      v > max) {
    std::ostringstream msg;
    msg << "--" << option << " expects a number in [" << min << ", " << max << "], got '" << text
        << "'";
    throw UsageError(msg.str());
  }
  return v;
}

std::chrono::milliseconds to_duration(const std::string& option, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  const std::string unit(end == nullptr ? "" : end);
  double scale = 0;
  if (unit.empty() || unit == "s") {
    scale = 1000;
  } else if (unit == "ms") {
    scale = 1;
  } else if (unit == "m" || unit == "min") {
    scale = 60000;
  }
  const double ms = v * scale;
  if (text.empty() || end == text.c_str() || scale == 0 || !std::isfinite(v) || v < 0 ||
      ms > 7 * 24 * 3600e3) {
    throw UsageError("--" + option + " expects a duration like 500ms, 2s or 1m, got '" + text +
                     "'");
  }
  return std::chrono::milliseconds(static_cast<std::int64_t>(std::llround(ms)));
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  std::string item;
  std::istringstream in(text);
  while (std::getline(in, item, ',')) {
    if (!item.empty()) {
      items.push_back(item);
    }
  }
  return items;
}

}  // namespace mtc::cli
