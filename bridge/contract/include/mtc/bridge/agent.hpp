// The MTConnect agent behind the HTTP server: turns a request
// ("GET /probe", "GET /mill/sample?from=10&count=5") into a response
// document. It knows nothing of sockets; the HTTP server (bridge/server)
// knows nothing of XML.
//
// Thread safety: every member may be called from any thread at once; the
// observation buffer underneath is internally synchronised.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "mtc/bridge/request.hpp"

namespace mtc::bridge {

struct Response {
  int status = 200;                       // HTTP status
  std::string content_type = "text/xml";  // text/xml, application/json, or a page's type
  std::string body;
};

// A streaming request (/sample or /current with interval=...): the server
// asks the agent for one part at a time and writes each as a multipart part.
struct StreamPlan {
  bool is_sample = true;                   // false: /current?interval
  std::chrono::milliseconds interval{0};   // minimum time between parts
  std::chrono::milliseconds heartbeat{0};  // idle time before an empty part
  std::uint64_t next_sequence = 0;         // where the next part starts
  RequestParameters parameters;            // what every part renders, read once
};

class Agent;

// Outcome of routing a request: either a complete response or a stream.
struct Routed {
  std::optional<Response> response;  // set for ordinary requests and errors
  std::optional<StreamPlan> stream;  // set for a valid streaming request
};

class Agent {
 public:
  virtual ~Agent() = default;

  // Routes one request. Never throws: bad requests (an unparsable target
  // included) become an MTConnectError document with the matching HTTP
  // status.
  virtual Routed route(const Request& request) noexcept = 0;

  // Splits `target` (parse_request) and routes it.
  Routed route(std::string_view method, std::string_view target) noexcept;

  // Next part of a stream: the document for observations from
  // plan.next_sequence on (advancing it), or, when there are none, an empty
  // (heartbeat) sample document. Never throws. A part whose status is not 200
  // is an MTConnectError (e.g. OUT_OF_RANGE: the stream fell behind the
  // buffer): write it, then end the stream.
  virtual Response next_part(StreamPlan& plan) noexcept = 0;

  // An MTConnectError document for a problem the front end found before
  // any route could (unparsable request, oversized header, request body,
  // too many connections), printed like the agent's own errors. `code` is
  // an MTConnect errorCode such as "INVALID_REQUEST". Never throws.
  virtual Response error_document(int status, std::string_view code,
                                  std::string_view message) noexcept = 0;

  // Sequence number the next observation will take; lets a stream wait.
  virtual std::uint64_t next_sequence() const noexcept = 0;

  // Blocks at most `timeout` until an observation with sequence >= `from`
  // exists; returns true if one does. Used by streaming connections.
  virtual bool wait_for(std::uint64_t from, std::chrono::milliseconds timeout) const = 0;

  // Registers a callback run (on the producer's thread; it must only hand
  // off) whenever new observations are added. Returns an id for removal.
  virtual std::uint64_t subscribe(std::function<void()> on_new_data) = 0;
  virtual void unsubscribe(std::uint64_t id) = 0;
};

}  // namespace mtc::bridge
