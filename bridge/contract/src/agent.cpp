#include "mtc/bridge/agent.hpp"

namespace mtc::bridge {

Routed Agent::route(std::string_view method, std::string_view target) noexcept {
  try {
    return route(parse_request(method, target));
  } catch (...) {  // out of memory while splitting the target
    Response response;
    response.status = 500;
    return Routed{response, std::nullopt};
  }
}

}  // namespace mtc::bridge
