// Internal, Cyclone DDS backend (MTC_CYCLONE builds): RAII for the C API's
// entities, its return codes as mtc::dds::Error, and the process's Cyclone
// domains. A dds_entity_t is deleted by its owner's destructor; a parent's
// deletion deletes its children, so children are declared after their
// parent and go first (a later dds_delete of a deleted child would fail).
#pragma once

#include <dds/dds.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "mtc/dds/error.hpp"

namespace mtc::dds::mw::cyclone {

// The project's code for a Cyclone return code; nullopt for DDS_RETCODE_OK
// and any other non-negative value (an entity handle, a count).
std::optional<ErrorCode> to_error_code(dds_return_t rc) noexcept;

// `rc` when it is not negative; throws Error(what, code) otherwise, the
// code named in the text as Cyclone spells it.
dds_return_t check(dds_return_t rc, const char* what);

// One entity (participant, topic, publisher, subscriber, writer, reader).
class Entity {
 public:
  Entity() = default;
  Entity(dds_entity_t handle, const char* what) : handle_(check(handle, what)), what_(what) {}
  ~Entity() { reset(); }
  Entity(const Entity&) = delete;
  Entity& operator=(const Entity&) = delete;
  Entity(Entity&& other) noexcept : handle_(other.handle_), what_(other.what_) {
    other.handle_ = 0;
  }
  Entity& operator=(Entity&& other) noexcept;
  dds_entity_t get() const noexcept { return handle_; }
  explicit operator bool() const noexcept { return handle_ > 0; }
  // Deletes the entity now; a failure is reported on stderr.
  void reset() noexcept;

 private:
  dds_entity_t handle_ = 0;
  const char* what_ = "";
};

struct ListenerDeleter {
  void operator()(dds_listener_t* l) const noexcept { dds_delete_listener(l); }
};
using Listener = std::unique_ptr<dds_listener_t, ListenerDeleter>;

// A Cyclone domain of this process: made with an explicit configuration
// (never CYCLONEDDS_URI) on first use and deleted with its last participant.
// Cyclone allows one domain per id in a process, so participants of one id
// share it; another recipe for a live id is a ConfigError (the domain's
// timing would silently be the first one's).
//
// The recipe is what a participant asks for (transport and timing), the
// configuration what the host made of it: the network transport's names the
// host's interfaces, read only when the domain is made. So a second
// participant of a domain reads no interfaces, and one made after an
// interface came or went shares the domain instead of being refused.
class Domain;
struct DomainRecipe {
  std::string recipe;
  std::function<std::string()> make_config;
};
std::shared_ptr<Domain> acquire_domain(dds_domainid_t id, const DomainRecipe& wanted);

}  // namespace mtc::dds::mw::cyclone
