// The agent's routes as data, the way the MTConnect reference agent keeps
// them: each Route is a list of path templates ("/{device}/sample") plus the
// query it reads (typed parameters with their allowed range and default)
// and a handler. RouteTable::match turns a split request target into the
// handler and its typed parameters, or into the RequestError the request
// deserves. Internal to mtc_bridge; the rows live in agent_routes.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mtc/bridge/agent.hpp"
#include "mtc/bridge/device_model.hpp"
#include "mtc/bridge/request.hpp"

namespace mtc::bridge::detail {

class AgentImpl;

// A request error: MTConnect errorCode, HTTP status, text.
struct RequestError {
  std::string_view code;
  int status = 400;
  std::string text;
};

// What routing made of a request: its parameters and the model's index of
// the device they name (resolved under the agent's lock).
struct Query : RequestParameters {
  std::optional<std::size_t> device_index;
};

using Handler = Routed (AgentImpl::*)(const Query& query);

// One query parameter: its name, the field it fills (which gives its type),
// the range an integer must fall in and the value it takes when absent.
struct Param {
  std::string_view name;
  std::optional<std::int64_t> RequestParameters::*integer = nullptr;
  std::optional<std::string> RequestParameters::*text = nullptr;
  bool RequestParameters::*flag = nullptr;  // "true" or "false"
  std::int64_t min = std::numeric_limits<std::int64_t>::min();
  std::int64_t max = std::numeric_limits<std::int64_t>::max();
  std::optional<std::int64_t> default_value;

  Param between(std::int64_t low, std::int64_t high) const;
  Param or_default(std::int64_t value) const;
};

Param integer_param(std::string_view name, std::optional<std::int64_t> RequestParameters::*field);
Param text_param(std::string_view name, std::optional<std::string> RequestParameters::*field);
Param flag_param(std::string_view name, bool RequestParameters::*field);

// The query a route reads. Checked in this order, as MTConnect agents do:
// every parameter named at most once and of its type (in query order);
// none of `foreign` (parameters of other requests); no pair of `exclusive`
// together; integers within their range. Names in neither list are ignored.
struct QuerySpec {
  std::vector<Param> params;
  std::vector<Param> foreign;
  std::string_view foreign_error;  // the text when one of `foreign` is given
  std::vector<std::pair<std::string_view, std::string_view>> exclusive;
};

struct Route {
  // "/", "/probe", "/{device}/sample": literal segments and placeholders,
  // "{device}" (a device of the model, by name or uuid) and "{asset}" (any).
  std::vector<std::string_view> paths;
  std::optional<QuerySpec> query;  // nullopt: the query is not read
  Handler handler = nullptr;
};

class RouteTable {
 public:
  RouteTable() = default;
  // Throws std::invalid_argument for a malformed path template.
  explicit RouteTable(std::vector<Route> routes);

  struct Match {
    const Route* route = nullptr;
    Query query;
  };

  // The route for `target` and its typed parameters. Among templates that
  // match, the one with the most literal segments wins (then table order).
  // When none matches, the error comes from the template that explains the
  // most of the path: an unknown device is NO_DEVICE, an unknown word
  // INVALID_URI (both 404). Throws RequestError.
  Match match(const RequestTarget& target, const DeviceModel& model) const;

 private:
  enum class Kind : std::uint8_t { Literal, Device, Asset };
  struct Segment {
    Kind kind = Kind::Literal;
    std::string_view literal;
  };
  struct Template {
    std::vector<Segment> segments;
    std::size_t literals = 0;
    std::size_t route = 0;  // index into routes_
  };

  std::vector<Route> routes_;
  // Every path of every route: most literal segments first, then table order.
  std::vector<Template> templates_;
};

// Reads `target.query` as `spec` says into `out`. Throws RequestError.
void read_query(const QuerySpec& spec, const RequestTarget& target, RequestParameters& out);

}  // namespace mtc::bridge::detail
