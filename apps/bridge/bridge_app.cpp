#include "bridge_app.hpp"

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <iostream>
#include <sstream>

#include "mtc/dds/middleware.hpp"

namespace mtc::bridge {

namespace {

// The agent's options with its warnings (DDS values no DataItem of the
// Devices file takes, once per item) logged on stderr.
AgentOptions logging_warnings(AgentOptions options) {
  options.on_warning = [](const std::string& warning) {
    std::cerr << "mtc-bridge: warning: " << warning << std::endl;
  };
  return options;
}

}  // namespace

BridgeApp::BridgeApp(const BridgeConfig& config)
    : config_(config), agent_(make_agent(logging_warnings(config.agent))) {
  server_ = std::make_unique<HttpServer>(agent_, config_.server);
  if (config_.shdr_enabled) shdr_ = std::make_unique<ShdrAdapter>(agent_, config_.shdr);
  observe_domains();
}

BridgeApp::~BridgeApp() {
  observers_.clear();  // no more intake before the server goes
  if (shdr_) shdr_->stop();
  if (server_) {
    server_->stop();
  }
}

void BridgeApp::observe_domains() {
  for (const int domain : config_.domain_ids) {
    dds::DomainObserverOptions options = config_.observer;
    options.domain_id = domain;
    // Callbacks run on the observer's dispatch thread (values, with
    // InlineSteps, on the middleware's receive thread); the agent's ingest
    // is thread-safe and takes its lock only for the append.
    MtconnectAgent* agent = agent_.get();
    dds::DomainObserverCallbacks callbacks;
    callbacks.on_device = [agent](const dds::ObservedDevice& device) { agent->add_device(device); };
    callbacks.on_value = [agent](const dds::ObservedValue& value) { agent->add_value(value); };
    callbacks.on_items_lost = [agent](const std::string& uuid,
                                      const std::vector<std::string>& items) {
      agent->items_lost(uuid, items);
    };
    callbacks.on_device_lost = [agent](const std::string& uuid) { agent->device_lost(uuid); };
    observers_.push_back(std::make_unique<dds::DomainObserver>(options, std::move(callbacks)));
  }
}

void BridgeApp::run(std::ostream& log) {
  boost::asio::io_context signals_context(1);
  boost::asio::signal_set signals(signals_context, SIGINT, SIGTERM);
  int received = 0;
  signals.async_wait([&](const boost::system::error_code& ec, int signal) {
    if (!ec) {
      received = signal;
    }
  });
  server_->start();
  if (shdr_) shdr_->start();

  std::ostringstream domains;
  for (std::size_t i = 0; i < config_.domain_ids.size(); ++i) {
    domains << (i == 0 ? "" : ",") << config_.domain_ids[i];
  }
  const bool v6 = server_->bind_address().find(':') != std::string::npos;
  log << "mtc-bridge: serving MTConnect " << to_string(agent_->schema_version()) << " on "
      << (server_->is_https() ? "https://" : "http://") << (v6 ? "[" : "")
      << server_->bind_address() << (v6 ? "]" : "") << ":" << server_->port() << "/ (DDS domains "
      << domains.str() << " over " << dds::to_string(observers_.front()->middleware())
      << (config_.observer.inline_steps ? "" : ", values via the dispatch thread")
      << "; devices from "
      << (config_.agent.devices_file.empty() ? std::string("DDS announcements")
                                             : config_.agent.devices_file)
      << (config_.observer.security_dir.empty()
              ? std::string("; DDS unsecured")
              : "; DDS-Security identity " + config_.observer.security_dir)
      << ")" << std::endl;
  if (shdr_) {
    const bool shdr_v6 = shdr_->bind_address().find(':') != std::string::npos;
    log << "mtc-bridge: SHDR adapter for MTConnect agents on " << (shdr_v6 ? "[" : "")
        << shdr_->bind_address() << (shdr_v6 ? "]" : "") << ":" << shdr_->port() << std::endl;
  }

  signals_context.run();  // until a signal arrives
  log << "mtc-bridge: signal " << received << ", stopping" << std::endl;
  observers_.clear();
  if (shdr_) shdr_->stop();
  server_->stop();
  log << "mtc-bridge: stopped" << std::endl;
}

}  // namespace mtc::bridge
