// Request targets as both sides of the Agent contract see them:
// "/mill/sample?from=10&count=5" split once into decoded path segments and
// query parameters. URI syntax only; what the segments and parameters mean
// is the agent's route table's business.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mtc::bridge {

struct RequestTarget {
  std::vector<std::string> segments;                       // decoded, non-empty
  std::vector<std::pair<std::string, std::string>> query;  // decoded, in order
};

// nullopt with `error` set for a target that is not an origin-form path
// ("/..."), has a bad %-escape, a NUL byte, or is absurdly long.
std::optional<RequestTarget> parse_target(std::string_view target, std::string& error);

}  // namespace mtc::bridge
