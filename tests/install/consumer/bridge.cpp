// Links mtc::bridge alone: an agent with no device yet answers /probe with
// an MTConnectDevices document.
#include <iostream>

#include "mtc/bridge/mtconnect_agent.hpp"

int main() {
  const auto agent = mtc::bridge::make_agent(mtc::bridge::AgentOptions{});
  const auto routed = agent->route("GET", "/probe");
  if (!routed.response) {
    return 1;
  }
  const bool devices = routed.response->body.find("MTConnectDevices") != std::string::npos;
  std::cout << "mtc::bridge: /probe -> " << routed.response->status << "\n";
  return routed.response->status == 200 && devices ? 0 : 1;
}
