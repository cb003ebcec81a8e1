#include "route_table.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace mtc::bridge::detail {
namespace {

enum class IntegerError { None, NotInteger, Overflow };

// Decimal integer, optional leading '-', nothing else (no spaces, no '+',
// no hex, no fraction).
IntegerError parse_integer(std::string_view text, std::int64_t& out) noexcept {
  bool negative = false;
  if (!text.empty() && text.front() == '-') {
    negative = true;
    text.remove_prefix(1);
  }
  if (text.empty()) return IntegerError::NotInteger;
  for (char c : text) {
    if (c < '0' || c > '9') return IntegerError::NotInteger;
  }
  constexpr auto kMax = static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());
  std::uint64_t value = 0;
  for (char c : text) {
    const auto digit = static_cast<std::uint64_t>(c - '0');
    if (value > (kMax - digit) / 10) return IntegerError::Overflow;
    value = value * 10 + digit;
  }
  out = negative ? -static_cast<std::int64_t>(value) : static_cast<std::int64_t>(value);
  return IntegerError::None;
}

RequestError invalid_request(std::string text) {
  return {"INVALID_REQUEST", 400, std::move(text)};
}

RequestError out_of_range(std::string text) {
  return {"OUT_OF_RANGE", 400, std::move(text)};
}

const Param* find_param(const std::vector<Param>& params, std::string_view name) {
  const auto it =
      std::find_if(params.begin(), params.end(), [&](const Param& p) { return p.name == name; });
  return it == params.end() ? nullptr : &*it;
}

bool is_given(const RequestTarget& target, std::string_view name) {
  return std::any_of(target.query.begin(), target.query.end(),
                     [&](const auto& pair) { return pair.first == name; });
}

// Stores one parameter's value in its field, typed; throws for text that is
// not of the parameter's type.
void store(const Param& param, const std::string& name, const std::string& value,
           RequestParameters& out) {
  if (param.text != nullptr) {
    out.*param.text = value;
    return;
  }
  if (param.flag != nullptr) {
    if (value != "true" && value != "false") {
      throw invalid_request("'" + name + "' must be true or false");
    }
    out.*param.flag = value == "true";
    return;
  }
  std::int64_t number = 0;
  switch (parse_integer(value, number)) {
    case IntegerError::NotInteger:
      throw invalid_request("'" + name + "' must be an integer, not '" + value.substr(0, 64) + "'");
    case IntegerError::Overflow:
      throw out_of_range("'" + name + "' is too large");
    case IntegerError::None:
      break;
  }
  out.*param.integer = number;
}

// How much of the path a template explained before it failed: a
// placeholder whose value is wrong explains more than a literal that differs
// at the same place. Equal depths mean the same error text.
struct Failure {
  std::size_t segment = 0;
  bool unknown_device = false;  // else: a literal that differs
  std::size_t depth() const noexcept { return 2 * segment + (unknown_device ? 1 : 0); }
};

}  // namespace

Param Param::between(std::int64_t low, std::int64_t high) const {
  Param p = *this;
  p.min = low;
  p.max = high;
  return p;
}

Param Param::or_default(std::int64_t value) const {
  Param p = *this;
  p.default_value = value;
  return p;
}

Param integer_param(std::string_view name, std::optional<std::int64_t> RequestParameters::*field) {
  Param p;
  p.name = name;
  p.integer = field;
  return p;
}

Param text_param(std::string_view name, std::optional<std::string> RequestParameters::*field) {
  Param p;
  p.name = name;
  p.text = field;
  return p;
}

Param flag_param(std::string_view name, bool RequestParameters::*field) {
  Param p;
  p.name = name;
  p.flag = field;
  return p;
}

void read_query(const QuerySpec& spec, const RequestTarget& target, RequestParameters& out) {
  RequestParameters foreign;  // typed only to report bad values first
  for (std::size_t i = 0; i < target.query.size(); ++i) {
    const auto& [name, value] = target.query[i];
    for (std::size_t j = 0; j < i; ++j) {
      if (target.query[j].first == name) throw invalid_request("'" + name + "' given twice");
    }
    if (const Param* param = find_param(spec.params, name)) {
      store(*param, name, value, out);
    } else if (const Param* other = find_param(spec.foreign, name)) {
      store(*other, name, value, foreign);
    }
  }
  for (const Param& other : spec.foreign) {
    if (is_given(target, other.name)) throw invalid_request(std::string(spec.foreign_error));
  }
  for (const auto& [first, second] : spec.exclusive) {
    if (is_given(target, first) && is_given(target, second)) {
      throw invalid_request("'" + std::string(first) + "' cannot be used with '" +
                            std::string(second) + "'");
    }
  }
  for (const Param& param : spec.params) {
    if (param.integer == nullptr) continue;
    auto& field = out.*param.integer;
    if (field && (*field < param.min || *field > param.max)) {
      throw out_of_range("'" + std::string(param.name) + "' must be between " +
                         std::to_string(param.min) + " and " + std::to_string(param.max));
    }
    if (!field && param.default_value) field = param.default_value;
  }
}

RouteTable::RouteTable(std::vector<Route> routes) : routes_(std::move(routes)) {
  for (std::size_t r = 0; r < routes_.size(); ++r) {
    for (std::string_view path : routes_[r].paths) {
      if (path.empty() || path.front() != '/') {
        throw std::invalid_argument("route path must start with '/': " + std::string(path));
      }
      Template t;
      t.route = r;
      path.remove_prefix(1);
      while (!path.empty()) {
        const auto slash = path.find('/');
        const std::string_view part = path.substr(0, slash);
        path = slash == std::string_view::npos ? std::string_view{} : path.substr(slash + 1);
        Segment s;
        if (part == "{device}") {
          s.kind = Kind::Device;
        } else if (part == "{asset}") {
          s.kind = Kind::Asset;
        } else if (part.empty() || part.front() == '{') {
          throw std::invalid_argument("bad route path segment '" + std::string(part) + "'");
        } else {
          s.literal = part;
          ++t.literals;
        }
        t.segments.push_back(s);
      }
      templates_.push_back(std::move(t));
    }
  }
  std::stable_sort(templates_.begin(), templates_.end(),
                   [](const Template& a, const Template& b) { return a.literals > b.literals; });
}

RouteTable::Match RouteTable::match(const RequestTarget& target, const DeviceModel& model) const {
  const auto& segments = target.segments;
  const Template* found = nullptr;
  std::optional<std::size_t> device;
  std::optional<Failure> failure;  // the deepest one
  // templates_ is ordered by literal count, so the first match is the best.
  for (const Template& t : templates_) {
    if (t.segments.size() != segments.size()) continue;
    std::optional<Failure> failed;
    device.reset();
    for (std::size_t k = 0; k < segments.size() && !failed; ++k) {
      const Segment& s = t.segments[k];
      if (s.kind == Kind::Literal && s.literal != segments[k]) {
        failed = Failure{k, false};
      } else if (s.kind == Kind::Device && !(device = model.find_device(segments[k]))) {
        failed = Failure{k, true};
      }
    }
    if (!failed) {
      found = &t;
      break;
    }
    if (!failure || failed->depth() > failure->depth()) failure = failed;
  }
  if (!found && !failure) throw RequestError{"INVALID_URI", 404, "unknown request path"};
  if (!found && failure->unknown_device) {
    throw RequestError{"NO_DEVICE", 404, "no device named '" + segments[failure->segment] + "'"};
  }
  if (!found) {
    throw RequestError{"INVALID_URI", 404, "unknown request '" + segments[failure->segment] + "'"};
  }

  Match m;
  m.route = &routes_[found->route];
  for (std::size_t k = 0; k < segments.size(); ++k) {
    if (found->segments[k].kind == Kind::Device) m.query.device = segments[k];
    if (found->segments[k].kind == Kind::Asset) m.query.asset = segments[k];
  }
  m.query.device_index = device;
  if (m.route->query) read_query(*m.route->query, target, m.query);
  return m;
}

}  // namespace mtc::bridge::detail
