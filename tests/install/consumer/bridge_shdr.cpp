// Links mtc::bridge_shdr alone: the SHDR adapter binds a free loopback port
// for an agent with no device yet, starts and stops.
#include <iostream>
#include <memory>

#include "mtc/bridge/shdr_adapter.hpp"

int main() {
  std::shared_ptr<mtc::bridge::MtconnectAgent> agent =
      mtc::bridge::make_agent(mtc::bridge::AgentOptions{});
  mtc::bridge::ShdrOptions options;
  options.port = 0;  // any free port on 127.0.0.1
  mtc::bridge::ShdrAdapter adapter(agent, options);
  adapter.start();
  const bool bound = adapter.port() != 0;
  adapter.stop();
  std::cout << "mtc::bridge_shdr: listened on port " << adapter.port() << "\n";
  return bound ? 0 : 1;
}
