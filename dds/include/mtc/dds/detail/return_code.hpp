// Internal: Fast DDS return codes -> mtc::dds::ErrorCode. Used by the
// runtime's sources and by tests; never included by a public header.
#pragma once

#include <fastrtps/types/TypesBase.h>

#include <optional>
#include <string>

#include "mtc/dds/error.hpp"

namespace mtc::dds::detail {

using ReturnCode = eprosima::fastrtps::types::ReturnCode_t;

// The project's code for a failed call; nullopt for RETCODE_OK and for a
// number Fast DDS 2.9 does not define.
std::optional<ErrorCode> to_error_code(const ReturnCode& code) noexcept;

// "RETCODE_BAD_PARAMETER", or "RETCODE_<n>" for an undefined number.
std::string return_code_name(const ReturnCode& code);

// Throws Error(what, code) unless code is RETCODE_OK; an undefined number
// becomes ErrorCode::Error with the number in the text.
void check(const ReturnCode& code, const std::string& what);

}  // namespace mtc::dds::detail
