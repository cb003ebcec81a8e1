#include "cyclone_entities.hpp"

#include <cstdio>
#include <map>
#include <mutex>

namespace mtc::dds::mw::cyclone {

std::optional<ErrorCode> to_error_code(dds_return_t rc) noexcept {
  switch (rc) {
    case DDS_RETCODE_UNSUPPORTED:
      return ErrorCode::Unsupported;
    case DDS_RETCODE_BAD_PARAMETER:
      return ErrorCode::BadParameter;
    case DDS_RETCODE_PRECONDITION_NOT_MET:
      return ErrorCode::PreconditionNotMet;
    case DDS_RETCODE_OUT_OF_RESOURCES:
      return ErrorCode::OutOfResources;
    case DDS_RETCODE_NOT_ENABLED:
      return ErrorCode::NotEnabled;
    case DDS_RETCODE_IMMUTABLE_POLICY:
      return ErrorCode::ImmutablePolicy;
    case DDS_RETCODE_INCONSISTENT_POLICY:
      return ErrorCode::InconsistentPolicy;
    case DDS_RETCODE_ALREADY_DELETED:
      return ErrorCode::AlreadyDeleted;
    case DDS_RETCODE_TIMEOUT:
      return ErrorCode::Timeout;
    case DDS_RETCODE_NO_DATA:
      return ErrorCode::NoData;
    case DDS_RETCODE_ILLEGAL_OPERATION:
      return ErrorCode::IllegalOperation;
    case DDS_RETCODE_NOT_ALLOWED_BY_SECURITY:
      return ErrorCode::NotAllowedBySecurity;
    default:
      // Every other negative code (DDS_RETCODE_ERROR and Cyclone's own
      // extensions) is the unspecified failure.
      return rc < 0 ? std::optional<ErrorCode>(ErrorCode::Error) : std::nullopt;
  }
}

dds_return_t check(dds_return_t rc, const char* what) {
  if (const auto code = to_error_code(rc)) {
    throw Error(std::string(what) + " failed: " + dds_strretcode(rc), *code);
  }
  return rc;
}

Entity& Entity::operator=(Entity&& other) noexcept {
  if (this != &other) {
    reset();
    handle_ = other.handle_;
    what_ = other.what_;
    other.handle_ = 0;
  }
  return *this;
}

void Entity::reset() noexcept {
  if (handle_ <= 0) return;
  const dds_return_t rc = dds_delete(handle_);
  if (rc < 0) std::fprintf(stderr, "mtc: dds_delete(%s): %s\n", what_, dds_strretcode(rc));
  handle_ = 0;
}

class Domain {
 public:
  Domain(dds_domainid_t id, std::string recipe, const std::string& config)
      : recipe_(std::move(recipe)),
        domain_(dds_create_domain(id, config.c_str()), "dds_create_domain") {}
  const std::string& recipe() const noexcept { return recipe_; }

 private:
  std::string recipe_;
  Entity domain_;
};

namespace {
std::mutex& domains_mutex() {
  static std::mutex mutex;
  return mutex;
}
}  // namespace

std::shared_ptr<Domain> acquire_domain(dds_domainid_t id, const DomainRecipe& wanted) {
  static std::map<dds_domainid_t, std::weak_ptr<Domain>> domains;
  const std::lock_guard<std::mutex> lock(domains_mutex());
  if (auto live = domains[id].lock()) {
    if (live->recipe() != wanted.recipe) {
      throw ConfigError("Cyclone DDS domain " + std::to_string(id) +
                        " already runs in this process with another timing or transport;"
                        " a Cyclone domain has one configuration per process");
    }
    return live;
  }
  // Deleted under the lock, so that a participant made meanwhile never
  // meets the old domain half gone (Cyclone would refuse the id).
  std::shared_ptr<Domain> made(new Domain(id, wanted.recipe, wanted.make_config()), [](Domain* d) {
    const std::lock_guard<std::mutex> held(domains_mutex());
    delete d;
  });
  domains[id] = made;
  return made;
}

}  // namespace mtc::dds::mw::cyclone
