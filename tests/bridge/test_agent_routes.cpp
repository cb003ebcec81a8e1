// The agent's side of the Agent contract beyond single documents: errors the
// HTTP front finds itself, printed by the agent.
#include <gtest/gtest.h>

#include "bridge_test_util.hpp"

namespace mtc::bridge {
namespace {

using test::Doc;

TEST(AgentContract, ErrorDocumentsForTheFrontEndCarryTheAgentsHeader) {
  auto agent = test::announced_cell(SchemaVersion::V1_6, 64);
  const Response r = agent->error_document(431, "INVALID_REQUEST", "header too large");
  EXPECT_EQ(r.status, 431);
  EXPECT_EQ(r.content_type, "text/xml");
  Doc d(r.body);
  ASSERT_TRUE(d.ok) << r.body;
  EXPECT_EQ(d.text("/MTConnectError/Errors/Error/@errorCode"), "INVALID_REQUEST");
  EXPECT_EQ(d.text("/MTConnectError/Errors/Error"), "header too large");
  EXPECT_EQ(d.text("/MTConnectError/Header/@instanceId"), "42");
  EXPECT_EQ(d.text("/MTConnectError/Header/@bufferSize"), "64");
  EXPECT_EQ(d.text("/MTConnectError/Header/@sender"), "mtc-bridge");
}

}  // namespace
}  // namespace mtc::bridge
