// Which DDS implementation carries an Equipment or a DomainObserver (issue 9
// section 3). Fast DDS is the default and always built; Cyclone DDS 0.10 is
// built in with MTC_CYCLONE=ON. Both speak the same IDL with the same QoS on
// the wire, so equipment on either share a cell (docs/design/middleware-layer.md).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace mtc::dds {

enum class Middleware : std::uint8_t {
  FastDds,  // eProsima Fast DDS 2.9: every transport, DDS-Security
  Cyclone,  // Eclipse Cyclone DDS 0.10: UDP (network and loopback), DDS-Security
};

inline constexpr std::array<Middleware, 2> kAllMiddlewares = {Middleware::FastDds,
                                                              Middleware::Cyclone};

// The one spelling of each, in command lines and configuration files alike:
// "fastdds", "cyclone".
std::string_view to_string(Middleware m) noexcept;
std::optional<Middleware> parse_middleware(std::string_view text) noexcept;

// Whether this build of the library has the backend (Cyclone: MTC_CYCLONE).
// Asking for one it lacks is a ConfigError when the participant is made.
bool middleware_available(Middleware m) noexcept;

// What `text` chooses in this build: the middleware, or the problem in words
// any tool can print after its own prefix ("unknown middleware 'x' (fastdds
// or cyclone)", or the CMake switch that builds a missing backend in). The
// command-line tools, the cell and the bridge's configuration all ask here,
// so they refuse alike.
struct MiddlewareChoice {
  std::optional<Middleware> middleware;
  std::string problem;  // set exactly when middleware is not
};
MiddlewareChoice choose_middleware(std::string_view text);

// "this build of mtconnect-dds has no cyclone backend (configure with ...)".
std::string missing_backend_message(Middleware m);

}  // namespace mtc::dds
