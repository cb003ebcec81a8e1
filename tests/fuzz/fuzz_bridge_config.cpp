// Fuzz target: mtc-bridge's configuration parser. The bytes are an
// agent.cfg-style file; parse_config_text either fills a BridgeConfig whose
// values lie in the ranges the bridge's parts accept, or throws ConfigError
// naming the file and line. Nothing else: no other exception, no crash.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "bridge_config.hpp"
#include "fuzz_support.hpp"
#include "mtc/bridge/mtconnect_agent.hpp"
#include "mtc/bridge/xml_text.hpp"
#include "mtc/qos/participant.hpp"

namespace {

void check_config(const mtc::bridge::BridgeConfig& config) {
  using mtc::fuzz::require;
  const auto& agent = config.agent;
  require(agent.buffer_size >= 2 && agent.buffer_size <= mtc::bridge::kMaxBufferSize,
          "BufferSize outside what make_agent accepts");
  require(agent.default_count > 0, "a default count of 0");
  require(agent.stream_heartbeat.count() > 0, "a stream heartbeat that is not positive");
  require(mtc::bridge::find_unfit_xml_char(agent.sender) == std::string::npos,
          "a Sender that cannot go into a document", agent.sender);
  require(!config.domain_ids.empty(), "no domain to observe");
  for (const int id : config.domain_ids) {
    require(id >= 0 && id <= mtc::qos::kMaxDomainId, "a domain id Fast DDS refuses");
  }
  require(config.server.io_threads > 0, "no I/O thread");
  require(config.server.header_limit > 0, "a header limit of 0");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  mtc::bridge::BridgeConfig config;
  try {
    const auto warnings = mtc::bridge::parse_config_text(config, text, "fuzz.cfg");
    for (const auto& warning : warnings) {
      mtc::fuzz::require(warning.rfind("fuzz.cfg:", 0) == 0, "a warning names no line", warning);
    }
    check_config(config);
  } catch (const mtc::bridge::ConfigError& error) {
    const std::string_view what = error.what();
    mtc::fuzz::require(what.rfind("fuzz.cfg:", 0) == 0, "the error names no file and line", what);
  }
  return 0;
}
