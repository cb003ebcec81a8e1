// RAII handles for Cyclone DDS 0.10 (C API) entities, for the interop tests.
// A handle is deleted in the destructor; declare children after their parent
// so that they go first (deleting a parent deletes its children, and a later
// dds_delete of a child would then fail). Every negative return code throws,
// naming the call; a failed deletion is reported on stderr (destructors never
// throw). The backend seam will grow this into dds/src/cyclone/
// (docs/design/middleware-layer.md).
#pragma once

#include <dds/dds.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

namespace mtc::test::cyclone {

// `rc` when it is not an error code; throws std::runtime_error otherwise.
inline dds_return_t check(dds_return_t rc, const char* what) {
  if (rc < 0) {
    throw std::runtime_error(std::string(what) + " failed: " + dds_strretcode(rc));
  }
  return rc;
}

class Entity {
 public:
  Entity(dds_entity_t handle, const char* what) : handle_(check(handle, what)), what_(what) {}
  ~Entity() {
    const dds_return_t rc = dds_delete(handle_);
    if (rc < 0) std::fprintf(stderr, "dds_delete(%s): %s\n", what_, dds_strretcode(rc));
  }
  Entity(const Entity&) = delete;
  Entity& operator=(const Entity&) = delete;
  dds_entity_t get() const noexcept { return handle_; }

 private:
  dds_entity_t handle_;
  const char* what_;
};

// A domain created with an explicit configuration (never CYCLONEDDS_URI from
// the environment) and one participant in it.
class DomainParticipant {
 public:
  DomainParticipant(dds_domainid_t id, const std::string& config)
      : domain_(dds_create_domain(id, config.c_str()), "dds_create_domain"),
        participant_(dds_create_participant(id, nullptr, nullptr), "dds_create_participant") {}
  dds_entity_t get() const noexcept { return participant_.get(); }

 private:
  Entity domain_;
  Entity participant_;
};

// Copies `from` into a bounded IDL string of Cyclone's C types (char[bound +
// 1]), cut at the bound and always terminated.
template <std::size_t N>
void copy_bounded(char (&to)[N], const std::string& from) {
  std::memset(to, 0, N);
  std::memcpy(to, from.data(), std::min(from.size(), N - 1));
}

}  // namespace mtc::test::cyclone
