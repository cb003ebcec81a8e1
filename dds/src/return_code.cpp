#include "mtc/dds/detail/return_code.hpp"

#include <array>
#include <utility>

namespace mtc::dds {

namespace {

using RC = eprosima::fastrtps::types::ReturnCode_t;

// Every Fast DDS 2.9 failure code and the project's code for it.
constexpr std::array<std::pair<std::uint32_t, ErrorCode>, 13> kCodes{{
    {RC::RETCODE_ERROR, ErrorCode::Error},
    {RC::RETCODE_UNSUPPORTED, ErrorCode::Unsupported},
    {RC::RETCODE_BAD_PARAMETER, ErrorCode::BadParameter},
    {RC::RETCODE_PRECONDITION_NOT_MET, ErrorCode::PreconditionNotMet},
    {RC::RETCODE_OUT_OF_RESOURCES, ErrorCode::OutOfResources},
    {RC::RETCODE_NOT_ENABLED, ErrorCode::NotEnabled},
    {RC::RETCODE_IMMUTABLE_POLICY, ErrorCode::ImmutablePolicy},
    {RC::RETCODE_INCONSISTENT_POLICY, ErrorCode::InconsistentPolicy},
    {RC::RETCODE_ALREADY_DELETED, ErrorCode::AlreadyDeleted},
    {RC::RETCODE_TIMEOUT, ErrorCode::Timeout},
    {RC::RETCODE_NO_DATA, ErrorCode::NoData},
    {RC::RETCODE_ILLEGAL_OPERATION, ErrorCode::IllegalOperation},
    {RC::RETCODE_NOT_ALLOWED_BY_SECURITY, ErrorCode::NotAllowedBySecurity},
}};

}  // namespace

std::string_view to_string(ErrorCode code) noexcept {
  switch (code) {
    case ErrorCode::Error:
      return "RETCODE_ERROR";
    case ErrorCode::Unsupported:
      return "RETCODE_UNSUPPORTED";
    case ErrorCode::BadParameter:
      return "RETCODE_BAD_PARAMETER";
    case ErrorCode::PreconditionNotMet:
      return "RETCODE_PRECONDITION_NOT_MET";
    case ErrorCode::OutOfResources:
      return "RETCODE_OUT_OF_RESOURCES";
    case ErrorCode::NotEnabled:
      return "RETCODE_NOT_ENABLED";
    case ErrorCode::ImmutablePolicy:
      return "RETCODE_IMMUTABLE_POLICY";
    case ErrorCode::InconsistentPolicy:
      return "RETCODE_INCONSISTENT_POLICY";
    case ErrorCode::AlreadyDeleted:
      return "RETCODE_ALREADY_DELETED";
    case ErrorCode::Timeout:
      return "RETCODE_TIMEOUT";
    case ErrorCode::NoData:
      return "RETCODE_NO_DATA";
    case ErrorCode::IllegalOperation:
      return "RETCODE_ILLEGAL_OPERATION";
    case ErrorCode::NotAllowedBySecurity:
      return "RETCODE_NOT_ALLOWED_BY_SECURITY";
    case ErrorCode::InvalidConfiguration:
      return "INVALID_CONFIGURATION";
  }
  return "RETCODE_ERROR";
}

namespace detail {

std::optional<ErrorCode> to_error_code(const ReturnCode& code) noexcept {
  for (const auto& [value, mapped] : kCodes) {
    if (code() == value) return mapped;
  }
  return std::nullopt;
}

std::string return_code_name(const ReturnCode& code) {
  if (code == ReturnCode::RETCODE_OK) return "RETCODE_OK";
  if (const auto mapped = to_error_code(code)) return std::string(to_string(*mapped));
  return "RETCODE_" + std::to_string(code());
}

void check(const ReturnCode& code, const std::string& what) {
  if (code == ReturnCode::RETCODE_OK) return;
  if (const auto mapped = to_error_code(code)) throw Error(what, *mapped);
  throw Error(what + " (" + return_code_name(code) + ")", ErrorCode::Error);
}

}  // namespace detail

}  // namespace mtc::dds
