// The DDS boundary turns every failed Fast DDS call into a typed exception
// carrying the project's own error code, so callers never see a silently
// ignored return code or a nullptr entity, and never a Fast DDS type. The
// mapping from Fast DDS return codes lives in the runtime's sources
// (mtc/dds/detail/return_code.hpp).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

namespace mtc::dds {

// Why a runtime call failed: one code per DDS return code the runtime maps
// (DDS 1.4, 2.2.1.1), plus a configuration that cannot work.
enum class ErrorCode : std::uint8_t {
  Error,                 // unspecified failure; also a create_* call that returned nullptr
  Unsupported,           // the operation is not supported by the implementation
  BadParameter,          // an argument was rejected
  PreconditionNotMet,    // the entity is not in a state that allows the call
  OutOfResources,        // a resource limit was reached
  NotEnabled,            // the entity is not enabled yet
  ImmutablePolicy,       // a QoS policy may not change after enabling
  InconsistentPolicy,    // QoS policies contradict each other
  AlreadyDeleted,        // the entity was deleted
  Timeout,               // the call timed out
  NoData,                // there was nothing to take
  IllegalOperation,      // the call is not allowed in this context
  NotAllowedBySecurity,  // DDS-Security refused it
  InvalidConfiguration,  // the options given to the runtime cannot work (ConfigError)
};

// "RETCODE_PRECONDITION_NOT_MET" etc. for the DDS codes (their DDS names, as
// logs and the Fast DDS documentation spell them), "INVALID_CONFIGURATION".
std::string_view to_string(ErrorCode code) noexcept;

class Error : public std::runtime_error {
 public:
  // what() reads "<what> (<code>)".
  Error(const std::string& what, ErrorCode code)
      : std::runtime_error(what + " (" + std::string(to_string(code)) + ")"), code_(code) {}

  ErrorCode code() const noexcept { return code_; }

 private:
  ErrorCode code_;
};

// A create_* call returned nullptr (Fast DDS gives no code for it).
class CreationError : public Error {
 public:
  explicit CreationError(const std::string& what) : Error(what, ErrorCode::Error) {}
};

// The configuration given to the runtime cannot work (bad uuid, duplicate
// interface, call in the wrong lifecycle phase, ...).
class ConfigError : public Error {
 public:
  explicit ConfigError(const std::string& what) : Error(what, ErrorCode::InvalidConfiguration) {}
};

}  // namespace mtc::dds
