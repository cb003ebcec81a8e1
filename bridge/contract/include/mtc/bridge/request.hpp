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

// A request as the front end read it: the method, the split target and the
// one header the agent reads, Accept (the document format a client asks for).
struct Request {
  std::string method;                   // "GET", "HEAD", ...
  std::optional<RequestTarget> target;  // nullopt: not a valid target ...
  std::string target_error;             // ... for this reason
  std::string accept;                   // the Accept header, empty when absent
};

Request parse_request(std::string_view method, std::string_view target,
                      std::string_view accept = {});

// The typed parameters of an MTConnect request, from its path and query,
// as the agent's route table read them (defaults included).
struct RequestParameters {
  std::optional<std::string> device;  // {device}: name or uuid
  std::optional<std::string> asset;   // {asset}: an asset id
  std::optional<std::string> path;    // XPath selecting data items
  std::optional<std::int64_t> at, from, to, count, interval, heartbeat;
  bool pretty = false;
  // MTConnect JSON instead of XML: `format=json`, or an Accept header naming
  // application/json (and no `format`), as the reference agent decides.
  bool json = false;
  // The client is a browser (Accept names text/html, no `format`): `/` then
  // serves the live page instead of the probe.
  bool browser = false;
};

}  // namespace mtc::bridge
