// The middleware named by the options, and the vocabulary of
// mtc/dds/middleware.hpp. MTC_HAVE_CYCLONE is defined for this library when
// the Cyclone backend is compiled in (dds/CMakeLists.txt).
#include "middleware.hpp"
#include "mtc/dds/error.hpp"
#include "mtc/dds/middleware.hpp"
#ifdef MTC_HAVE_CYCLONE
#include "cyclone_backend.hpp"
#endif

namespace mtc::dds {

std::string_view to_string(Middleware m) noexcept {
  return m == Middleware::Cyclone ? "cyclone" : "fastdds";
}

std::optional<Middleware> parse_middleware(std::string_view text) noexcept {
  for (const auto m : kAllMiddlewares) {
    if (text == to_string(m)) return m;
  }
  return std::nullopt;
}

bool middleware_available(Middleware m) noexcept {
#ifdef MTC_HAVE_CYCLONE
  return m == Middleware::FastDds || m == Middleware::Cyclone;
#else
  return m == Middleware::FastDds;
#endif
}

MiddlewareChoice choose_middleware(std::string_view text) {
  MiddlewareChoice choice;
  const auto parsed = parse_middleware(text);
  if (!parsed) {
    choice.problem = "unknown middleware '" + std::string(text) + "' (fastdds or cyclone)";
  } else if (!middleware_available(*parsed)) {
    choice.problem = missing_backend_message(*parsed);
  } else {
    choice.middleware = parsed;
  }
  return choice;
}

std::string missing_backend_message(Middleware m) {
  return "this build of mtconnect-dds has no " + std::string(to_string(m)) +
         " backend (configure with -DMTC_CYCLONE=ON)";
}

namespace mw {

std::unique_ptr<Participant> make_participant(Middleware middleware, int domain_id,
                                              const qos::ParticipantConfig& config) {
  switch (middleware) {
    case Middleware::FastDds:
      return make_fastdds_participant(domain_id, config);
    case Middleware::Cyclone:
#ifdef MTC_HAVE_CYCLONE
      return make_cyclone_participant(domain_id, config);
#else
      break;
#endif
  }
  throw ConfigError(missing_backend_message(middleware));
}

}  // namespace mw
}  // namespace mtc::dds
