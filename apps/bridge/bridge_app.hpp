// The mtc-bridge process: one MtconnectAgent fed by a DomainObserver per DDS
// domain, served over HTTP until SIGINT/SIGTERM.
#pragma once

#include <memory>
#include <ostream>
#include <vector>

#include "bridge_config.hpp"
#include "mtc/bridge/http_server.hpp"
#include "mtc/bridge/mtconnect_agent.hpp"
#include "mtc/bridge/shdr_adapter.hpp"
#include "mtc/dds/domain_observer.hpp"

namespace mtc::bridge {

class BridgeApp {
 public:
  // Builds the agent (throws ModelError for a bad Devices file), binds the
  // HTTP port (std::system_error) and joins the DDS domains (mtc::dds
  // errors), and the SHDR port when configured. Nothing is served until
  // run().
  explicit BridgeApp(const BridgeConfig& config);
  ~BridgeApp();
  BridgeApp(const BridgeApp&) = delete;
  BridgeApp& operator=(const BridgeApp&) = delete;

  // Serves until SIGINT or SIGTERM, then stops DDS intake first and HTTP
  // last (streams get their closing boundary). Prints where it listens.
  void run(std::ostream& log);

  std::uint16_t port() const noexcept { return server_->port(); }

 private:
  void observe_domains();

  BridgeConfig config_;
  std::shared_ptr<MtconnectAgent> agent_;
  std::unique_ptr<HttpServer> server_;
  std::unique_ptr<ShdrAdapter> shdr_;  // when configured
  std::vector<std::unique_ptr<dds::DomainObserver>> observers_;
};

}  // namespace mtc::bridge
