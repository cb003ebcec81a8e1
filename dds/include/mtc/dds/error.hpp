// The DDS boundary turns every failed Fast DDS call into a typed exception
// carrying the DDS return code, so callers never see a silently ignored
// ReturnCode_t or a nullptr entity.
#pragma once

#include <stdexcept>
#include <string>

#include <fastrtps/types/TypesBase.h>

namespace mtc::dds {

using ReturnCode = eprosima::fastrtps::types::ReturnCode_t;

class Error : public std::runtime_error {
 public:
  Error(const std::string& what, ReturnCode code)
      : std::runtime_error(what + " (" + name(code) + ")"), code_(code) {}

  ReturnCode code() const noexcept { return code_; }

  // "RETCODE_PRECONDITION_NOT_MET" etc.
  static std::string name(const ReturnCode& code);

 private:
  ReturnCode code_;
};

// A create_* call returned nullptr (Fast DDS gives no code: RETCODE_ERROR).
class CreationError : public Error {
 public:
  explicit CreationError(const std::string& what)
      : Error(what, ReturnCode::RETCODE_ERROR) {}
};

// The configuration given to the runtime cannot work (bad uuid, duplicate
// interface, call in the wrong lifecycle phase, ...).
class ConfigError : public Error {
 public:
  explicit ConfigError(const std::string& what)
      : Error(what, ReturnCode::RETCODE_BAD_PARAMETER) {}
};

// Throws Error(what, code) unless code is RETCODE_OK.
void check(const ReturnCode& code, const std::string& what);

}  // namespace mtc::dds
