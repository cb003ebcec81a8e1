// Fuzz target: an HTTP request as a client sends it. The bytes go through
// the parser the bridge's sessions use (Beast, with the server's header
// limit), the target through parse_request (path segments, %-escapes, the
// query), and the request through the agent's route table (typed query
// parameters, the `path` filter, streams' first part). Every answer must be
// a complete XML document.
#include <boost/asio/buffer.hpp>
#include <boost/beast/http/empty_body.hpp>
#include <boost/beast/http/error.hpp>
#include <boost/beast/http/parser.hpp>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "fuzz_support.hpp"
#include "mtc/bridge/http_server.hpp"
#include "mtc/bridge/mtconnect_agent.hpp"
#include "mtc/bridge/request.hpp"

namespace {

namespace http = boost::beast::http;

// The sample cell's Devices file, with a few observations in its buffer.
mtc::bridge::MtconnectAgent& agent() {
  static const auto instance = [] {
    mtc::bridge::AgentOptions options;
    options.devices_file = MTC_FUZZ_DEVICES_FILE;
    options.buffer_size = 64;
    options.instance_id = 1;
    auto made = mtc::bridge::make_agent(options);
    mtc::core::ObservedValue value;
    value.device_uuid = "cell-machine";
    value.data_item_id = "machine_material_handler_material_load_request";
    value.service = mtc::core::Service::MaterialLoad;
    value.sub_type = mtc::core::SubType::Request;
    for (auto state : {mtc::core::InteractionState::Ready, mtc::core::InteractionState::Active}) {
      value.state = state;
      ++value.sequence_number;
      made->add_value(value);
    }
    return made;
  }();
  return *instance;
}

void check_routed(mtc::bridge::Routed routed) {
  mtc::fuzz::require(routed.response.has_value() != routed.stream.has_value(),
                     "route gave neither or both of a response and a stream");
  if (routed.response) {
    mtc::fuzz::require_xml_document(routed.response->body, "route answer");
    return;
  }
  const auto part = agent().next_part(*routed.stream);
  mtc::fuzz::require_xml_document(part.body, "first stream part");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  http::request_parser<http::empty_body> parser;
  parser.header_limit(static_cast<std::uint32_t>(mtc::bridge::ServerOptions{}.header_limit));
  boost::beast::error_code ec;
  std::size_t used = 0;
  while (used < size && !parser.is_header_done()) {
    const std::size_t n = parser.put(boost::asio::buffer(data + used, size - used), ec);
    used += n;
    if (ec == http::error::need_more) ec = {};
    if (ec || n == 0) break;
  }
  if (!parser.is_header_done()) {
    // What a session answers to a request it cannot read.
    const auto error =
        agent().error_document(400, "INVALID_REQUEST", "malformed HTTP request: " + ec.message());
    mtc::fuzz::require_xml_document(error.body, "error document");
    return 0;
  }
  const auto& message = parser.get();
  const std::string_view method(message.method_string().data(), message.method_string().size());
  const std::string_view target(message.target().data(), message.target().size());
  (void)message.keep_alive();
  check_routed(agent().route(mtc::bridge::parse_request(method, target)));
  return 0;
}
