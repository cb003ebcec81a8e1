// Errors carry the project's own codes: every Fast DDS failure code maps to
// one, the text names it, and configuration errors are told apart. No DDS
// entity is created here.
#include <gtest/gtest.h>

#include <set>

#include "mtc/dds/detail/return_code.hpp"
#include "mtc/dds/error.hpp"

namespace mtc::dds {
namespace {

using detail::ReturnCode;

TEST(Error, EveryFastDdsFailureMapsToItsOwnCode) {
  std::set<ErrorCode> seen;
  for (std::uint32_t n = ReturnCode::RETCODE_ERROR;
       n <= ReturnCode::RETCODE_NOT_ALLOWED_BY_SECURITY; ++n) {
    const auto mapped = detail::to_error_code(ReturnCode(n));
    ASSERT_TRUE(mapped.has_value()) << n;
    // The DDS name survives the mapping.
    EXPECT_EQ(to_string(*mapped), detail::return_code_name(ReturnCode(n)));
    seen.insert(*mapped);
  }
  EXPECT_EQ(seen.size(), 13u);
  EXPECT_EQ(detail::to_error_code(ReturnCode::RETCODE_PRECONDITION_NOT_MET),
            ErrorCode::PreconditionNotMet);
  EXPECT_FALSE(detail::to_error_code(ReturnCode::RETCODE_OK).has_value());
  EXPECT_FALSE(detail::to_error_code(ReturnCode(99)).has_value());
}

TEST(Error, CheckThrowsTheMappedCodeAndNamesIt) {
  EXPECT_NO_THROW(detail::check(ReturnCode::RETCODE_OK, "write"));
  try {
    detail::check(ReturnCode::RETCODE_OUT_OF_RESOURCES, "write on mtc/InterfaceState");
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::OutOfResources);
    EXPECT_STREQ(e.what(), "write on mtc/InterfaceState (RETCODE_OUT_OF_RESOURCES)");
  }
  try {
    detail::check(ReturnCode(99), "write");
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::Error);
    EXPECT_NE(std::string(e.what()).find("RETCODE_99"), std::string::npos) << e.what();
  }
}

TEST(Error, ConfigAndCreationErrorsAreTyped) {
  const ConfigError config("interface \"mh1\" declared twice");
  EXPECT_EQ(config.code(), ErrorCode::InvalidConfiguration);
  EXPECT_STREQ(config.what(), "interface \"mh1\" declared twice (INVALID_CONFIGURATION)");
  const CreationError creation("create_topic mtc/DoorState");
  EXPECT_EQ(creation.code(), ErrorCode::Error);
  const Error& as_error = config;
  EXPECT_EQ(as_error.code(), ErrorCode::InvalidConfiguration);
}

}  // namespace
}  // namespace mtc::dds
