// Requests as both sides of the Agent contract see them. The front end
// splits a target once ("/mill/sample?from=10&count=5" into decoded path
// segments and query parameters: URI syntax only); the agent's route table
// reads them once into typed RequestParameters, which a stream keeps.
#pragma once

#include <cstdint>
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

// A request as the front end read it: the method and the split target.
struct Request {
  std::string method;                   // "GET", "HEAD", ...
  std::optional<RequestTarget> target;  // nullopt: not a valid target ...
  std::string target_error;             // ... for this reason
};

Request parse_request(std::string_view method, std::string_view target);

// The typed parameters of an MTConnect request, from its path and query,
// as the agent's route table read them (defaults included).
struct RequestParameters {
  std::optional<std::string> device;  // {device}: name or uuid
  std::optional<std::string> asset;   // {asset}: an asset id
  std::optional<std::string> path;    // XPath selecting data items
  std::optional<std::int64_t> at, from, to, count, interval, heartbeat;
  bool pretty = false;
};

}  // namespace mtc::bridge
