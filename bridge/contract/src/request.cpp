#include "mtc/bridge/request.hpp"

namespace mtc::bridge {

namespace {

constexpr std::size_t kMaxTarget = 8192;

int hex_value(char c) noexcept {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// %-decoding; '+' means a space only in the query part.
bool decode(std::string_view in, bool plus_is_space, std::string& out) {
  out.clear();
  out.reserve(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) {
    char c = in[i];
    if (c == '%') {
      if (i + 2 >= in.size()) return false;
      const int hi = hex_value(in[i + 1]);
      const int lo = hex_value(in[i + 2]);
      if (hi < 0 || lo < 0) return false;
      c = static_cast<char>(hi * 16 + lo);
      i += 2;
    } else if (c == '+' && plus_is_space) {
      c = ' ';
    }
    if (c == '\0') return false;
    out.push_back(c);
  }
  return true;
}

}  // namespace

std::optional<RequestTarget> parse_target(std::string_view target, std::string& error) {
  if (target.size() > kMaxTarget) {
    error = "the request target is too long";
    return std::nullopt;
  }
  if (target.empty() || target.front() != '/') {
    error = "the request target must start with '/'";
    return std::nullopt;
  }
  if (const auto hash = target.find('#'); hash != std::string_view::npos) {
    target = target.substr(0, hash);
  }
  std::string_view path = target;
  std::string_view query;
  if (const auto q = target.find('?'); q != std::string_view::npos) {
    path = target.substr(0, q);
    query = target.substr(q + 1);
  }
  RequestTarget out;
  std::string decoded;
  while (!path.empty()) {
    const auto slash = path.find('/');
    const std::string_view part = path.substr(0, slash);
    path = slash == std::string_view::npos ? std::string_view{} : path.substr(slash + 1);
    if (part.empty()) continue;
    if (!decode(part, false, decoded)) {
      error = "bad %-escape in the request path";
      return std::nullopt;
    }
    out.segments.push_back(decoded);
  }
  while (!query.empty()) {
    const auto amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    query = amp == std::string_view::npos ? std::string_view{} : query.substr(amp + 1);
    if (pair.empty()) continue;
    const auto eq = pair.find('=');
    std::string name;
    std::string value;
    if (!decode(pair.substr(0, eq), true, name) ||
        (eq != std::string_view::npos && !decode(pair.substr(eq + 1), true, value))) {
      error = "bad %-escape in the query";
      return std::nullopt;
    }
    out.query.emplace_back(std::move(name), std::move(value));
  }
  return out;
}

Request parse_request(std::string_view method, std::string_view target, std::string_view accept) {
  Request request;
  request.method = std::string(method);
  request.target = parse_target(target, request.target_error);
  request.accept = std::string(accept);
  return request;
}

}  // namespace mtc::bridge
