// Every (state, event) pair of the requester machine (Table 5), under the
// 1.6/1.8 profile and the 1.3 profile.
#include <gtest/gtest.h>

#include <set>

#include "table_expectations.hpp"

namespace mtc::core::testing_support {
namespace {

using E = Event;
using S = InteractionState;
using N = Notice;
using R = Reason;

// Events whose outcome is "nothing to do" in most states.
std::vector<Expect> idle_timers(S s) {
  return {both(E::ResponseTimeout, s, N::None), both(E::ServiceTimeout, s, N::None),
          both(E::CompletionAckTimeout, s, N::None), both(E::FailAckTimeout, s, N::None),
          both(E::FailResetTimeout, s, N::None)};
}

std::vector<Expect> with(std::vector<Expect> rows, const std::vector<Expect>& more) {
  rows.insert(rows.end(), more.begin(), more.end());
  return rows;
}

// clang-format off
// DISABLED (Table 3): NOT_READY, every command refused.
std::vector<Expect> disabled_commands() {
  return {
      both(E::Request, S::NotReady, N::Rejected, R::InterfaceDisabled),
      both(E::Accept, S::NotReady, N::Rejected, R::WrongRole),
      both(E::Complete, S::NotReady, N::Rejected, R::WrongRole),
      both(E::Fail, S::NotReady, N::Rejected, R::InterfaceDisabled),
      both(E::RecoverReady, S::NotReady, N::Rejected, R::InterfaceDisabled),
      both(E::RecoverNotReady, S::NotReady, N::Rejected, R::InterfaceDisabled),
      both(E::SetReady, S::NotReady, N::Rejected, R::InterfaceDisabled),
      both(E::SetNotReady, S::NotReady, N::Rejected, R::InterfaceDisabled),
      both(E::Disable, S::NotReady, N::None),
      both(E::Reevaluate, S::NotReady, N::None),
      both(E::SeenUnavailable, S::NotReady, N::CommsLost, R::CommsLost),
      both(E::SeenInvalid, S::NotReady, N::ProtocolViolation, R::UnknownValue),
  };
}

// READY, response READY.
SetupExpectations requester_ready() {
  return {Setup::Ready, with({
      both(E::Request, S::Active, N::RequestIssued),  // Table 1 step 1
      both(E::Accept, S::Ready, N::Rejected, R::WrongRole),
      both(E::Complete, S::Ready, N::Rejected, R::WrongRole),
      both(E::Fail, S::Fail, N::Failed, R::Application),  // Table 5 FAIL condition 1
      both(E::RecoverReady, S::Ready, N::Rejected, R::NotFailed),
      both(E::RecoverNotReady, S::Ready, N::Rejected, R::NotFailed),
      both(E::SetReady, S::Ready, N::None),
      both(E::SetNotReady, S::NotReady, N::ReadinessChanged, R::Application),
      both(E::Disable, S::NotReady, N::Disabled, R::InterfaceDisabled),  // Table 3
      both(E::Enable, S::Ready, N::None),
      both(E::Reevaluate, S::Ready, N::None),
      both(E::SeenNotReady, S::Ready, N::None),
      both(E::SeenReady, S::Ready, N::None),  // no change of the response
      // A response goes ACTIVE/COMPLETE only for an ACTIVE request (Table 6).
      both(E::SeenActive, S::Fail, N::ProtocolViolation, R::ActiveWithoutRequest),
      both(E::SeenComplete, S::Fail, N::ProtocolViolation, R::CompleteWithoutRequest),
      // Table 5 condition 2 (MUST go FAIL); 1.3 returns to / stays READY.
      differ(E::SeenFail, S::Fail, N::CounterpartFailed, R::CounterpartFail,
             S::Ready, N::CounterpartFailed, R::CounterpartFail),
      // Scenario 6 (1.6: both sides FAIL); 1.3 idle side waits for reconnection.
      differ(E::SeenUnavailable, S::Fail, N::CommsLost, R::CommsLost,
             S::Ready, N::CommsLost, R::CommsLost),
      both(E::SeenInvalid, S::Fail, N::ProtocolViolation, R::UnknownValue),
  }, idle_timers(S::Ready))};
}

// NOT_READY (the application's choice), response READY.
SetupExpectations requester_not_ready() {
  return {Setup::NotReady, with({
      both(E::Request, S::NotReady, N::Rejected, R::NotReady),
      both(E::Accept, S::NotReady, N::Rejected, R::WrongRole),
      both(E::Complete, S::NotReady, N::Rejected, R::WrongRole),
      both(E::Fail, S::Fail, N::Failed, R::Application),
      both(E::RecoverReady, S::NotReady, N::Rejected, R::NotFailed),
      both(E::RecoverNotReady, S::NotReady, N::Rejected, R::NotFailed),
      both(E::SetReady, S::Ready, N::ReadinessChanged, R::Application),
      both(E::SetNotReady, S::NotReady, N::None),
      both(E::Disable, S::NotReady, N::Disabled, R::InterfaceDisabled),
      both(E::Enable, S::NotReady, N::None),
      both(E::Reevaluate, S::NotReady, N::None),  // still wants NOT_READY
      both(E::SeenNotReady, S::NotReady, N::None),
      both(E::SeenReady, S::NotReady, N::None),
      both(E::SeenActive, S::Fail, N::ProtocolViolation, R::ActiveWithoutRequest),
      both(E::SeenComplete, S::Fail, N::ProtocolViolation, R::CompleteWithoutRequest),
      differ(E::SeenFail, S::Fail, N::CounterpartFailed, R::CounterpartFail,
             S::NotReady, N::CounterpartFailed, R::CounterpartFail),
      differ(E::SeenUnavailable, S::Fail, N::CommsLost, R::CommsLost,
             S::NotReady, N::CommsLost, R::CommsLost),
      both(E::SeenInvalid, S::Fail, N::ProtocolViolation, R::UnknownValue),
  }, idle_timers(S::NotReady))};
}

// ACTIVE, response still READY (step 2 not yet seen).
SetupExpectations requester_active() {
  return {Setup::Active, {
      both(E::Request, S::Active, N::Rejected, R::AlreadyActive),
      both(E::Accept, S::Active, N::Rejected, R::WrongRole),
      both(E::Complete, S::Active, N::Rejected, R::WrongRole),
      both(E::Fail, S::Fail, N::Failed, R::Application),
      both(E::RecoverReady, S::Active, N::Rejected, R::NotFailed),
      both(E::RecoverNotReady, S::Active, N::Rejected, R::NotFailed),
      // Going back to READY/NOT_READY unasked is scenario 4's failure.
      both(E::SetReady, S::Active, N::Rejected, R::NotIdle),
      both(E::SetNotReady, S::Active, N::Rejected, R::NotIdle),
      both(E::Disable, S::NotReady, N::Disabled, R::InterfaceDisabled),
      both(E::Enable, S::Active, N::None),
      both(E::Reevaluate, S::Active, N::None),
      // The responder refused (went NOT_READY) before accepting.
      differ(E::SeenNotReady, S::Fail, N::CounterpartFailed, R::CounterpartNotReady,
             S::Ready, N::CounterpartFailed, R::CounterpartNotReady),
      both(E::SeenReady, S::Active, N::None),
      both(E::SeenActive, S::Active, N::Accepted),  // step 3 seen
      both(E::SeenComplete, S::Fail, N::ProtocolViolation, R::CompleteWithoutActive),
      // Scenario 1: 1.6 MUST FAIL; 1.3 MUST go back to READY.
      differ(E::SeenFail, S::Fail, N::CounterpartFailed, R::CounterpartFail,
             S::Ready, N::CounterpartFailed, R::CounterpartFail),
      both(E::SeenUnavailable, S::Fail, N::CommsLost, R::CommsLost),
      both(E::SeenInvalid, S::Fail, N::ProtocolViolation, R::UnknownValue),
      both(E::ResponseTimeout, S::Fail, N::TimedOut, R::ResponseTimeout),
      both(E::ServiceTimeout, S::Fail, N::TimedOut, R::ServiceTimeout),
      both(E::CompletionAckTimeout, S::Active, N::None),
      both(E::FailAckTimeout, S::Active, N::None),
      both(E::FailResetTimeout, S::Active, N::None),
  }};
}

// ACTIVE, response ACTIVE (performing the service).
SetupExpectations requester_active_engaged() {
  return {Setup::ActiveEngaged, {
      both(E::Request, S::Active, N::Rejected, R::AlreadyActive),
      both(E::Accept, S::Active, N::Rejected, R::WrongRole),
      both(E::Complete, S::Active, N::Rejected, R::WrongRole),
      both(E::Fail, S::Fail, N::Failed, R::Application),  // scenario 3
      both(E::RecoverReady, S::Active, N::Rejected, R::NotFailed),
      both(E::RecoverNotReady, S::Active, N::Rejected, R::NotFailed),
      both(E::SetReady, S::Active, N::Rejected, R::NotIdle),
      both(E::SetNotReady, S::Active, N::Rejected, R::NotIdle),
      both(E::Disable, S::NotReady, N::Disabled, R::InterfaceDisabled),
      both(E::Enable, S::Active, N::None),
      both(E::Reevaluate, S::Active, N::None),
      // Scenario 5 / 1.3 "no FAIL state": leaving ACTIVE early = FAIL.
      differ(E::SeenNotReady, S::Fail, N::CounterpartFailed, R::CounterpartLeftActive,
             S::Ready, N::CounterpartFailed, R::CounterpartLeftActive),
      differ(E::SeenReady, S::Fail, N::CounterpartFailed, R::CounterpartLeftActive,
             S::Ready, N::CounterpartFailed, R::CounterpartLeftActive),
      both(E::SeenActive, S::Active, N::None),
      both(E::SeenComplete, S::Ready, N::Completed),  // steps 5-6
      // Scenario 2.
      differ(E::SeenFail, S::Fail, N::CounterpartFailed, R::CounterpartFail,
             S::Ready, N::CounterpartFailed, R::CounterpartFail),
      both(E::SeenUnavailable, S::Fail, N::CommsLost, R::CommsLost),
      both(E::SeenInvalid, S::Fail, N::ProtocolViolation, R::UnknownValue),
      both(E::ResponseTimeout, S::Active, N::None),  // the response did come
      both(E::ServiceTimeout, S::Fail, N::TimedOut, R::ServiceTimeout),
      both(E::CompletionAckTimeout, S::Active, N::None),
      both(E::FailAckTimeout, S::Active, N::None),
      both(E::FailResetTimeout, S::Active, N::None),
  }};
}

// FAIL by own failure, response still READY: not acknowledged.
SetupExpectations requester_fail() {
  return {Setup::Fail, {
      both(E::Request, S::Fail, N::Rejected, R::AlreadyFailed),
      both(E::Accept, S::Fail, N::Rejected, R::WrongRole),
      both(E::Complete, S::Fail, N::Rejected, R::WrongRole),
      both(E::Fail, S::Fail, N::Rejected, R::AlreadyFailed),
      // Table 5 ACTIONS: SHOULD NOT leave FAIL until the responder is FAIL.
      both(E::RecoverReady, S::Fail, N::Rejected, R::FailNotAcknowledged),
      both(E::RecoverNotReady, S::Fail, N::Rejected, R::FailNotAcknowledged),
      both(E::SetReady, S::Fail, N::Rejected, R::NotIdle),
      both(E::SetNotReady, S::Fail, N::Rejected, R::NotIdle),
      both(E::Disable, S::NotReady, N::Disabled, R::InterfaceDisabled),
      both(E::Enable, S::Fail, N::None),
      both(E::Reevaluate, S::Fail, N::None),
      both(E::SeenNotReady, S::Fail, N::None),
      both(E::SeenReady, S::Fail, N::None),
      both(E::SeenActive, S::Fail, N::None),
      both(E::SeenComplete, S::Fail, N::None),
      both(E::SeenFail, S::Fail, N::FailAcknowledged),
      both(E::SeenUnavailable, S::Fail, N::CommsLost, R::CommsLost),
      both(E::SeenInvalid, S::Fail, N::ProtocolViolation, R::UnknownValue),
      both(E::ResponseTimeout, S::Fail, N::None),
      both(E::ServiceTimeout, S::Fail, N::None),
      both(E::CompletionAckTimeout, S::Fail, N::None),
      both(E::FailAckTimeout, S::Fail, N::TimedOut, R::FailAckTimeout),
      // 1.3: FAIL may go back to READY after a period of time.
      differ(E::FailResetTimeout, S::Fail, N::None, R::None,
             S::Ready, N::Recovered, R::FailResetTimeout),
  }};
}

// FAIL, response FAIL too: acknowledged, recovery allowed.
SetupExpectations requester_fail_acknowledged() {
  return {Setup::FailAcknowledged, {
      both(E::Request, S::Fail, N::Rejected, R::AlreadyFailed),
      both(E::Accept, S::Fail, N::Rejected, R::WrongRole),
      both(E::Complete, S::Fail, N::Rejected, R::WrongRole),
      both(E::Fail, S::Fail, N::Rejected, R::AlreadyFailed),
      both(E::RecoverReady, S::Ready, N::Recovered),
      both(E::RecoverNotReady, S::NotReady, N::Recovered),
      both(E::SetReady, S::Fail, N::Rejected, R::NotIdle),
      both(E::SetNotReady, S::Fail, N::Rejected, R::NotIdle),
      both(E::Disable, S::NotReady, N::Disabled, R::InterfaceDisabled),
      both(E::Enable, S::Fail, N::None),
      both(E::Reevaluate, S::Fail, N::None),
      both(E::SeenNotReady, S::Fail, N::None),
      both(E::SeenReady, S::Fail, N::None),
      both(E::SeenActive, S::Fail, N::None),
      both(E::SeenComplete, S::Fail, N::None),
      both(E::SeenFail, S::Fail, N::None),
      both(E::SeenUnavailable, S::Fail, N::CommsLost, R::CommsLost),
      both(E::SeenInvalid, S::Fail, N::ProtocolViolation, R::UnknownValue),
      both(E::ResponseTimeout, S::Fail, N::None),
      both(E::ServiceTimeout, S::Fail, N::None),
      both(E::CompletionAckTimeout, S::Fail, N::None),
      both(E::FailAckTimeout, S::Fail, N::None),
      differ(E::FailResetTimeout, S::Fail, N::None, R::None,
             S::Ready, N::Recovered, R::FailResetTimeout),
  }};
}

SetupExpectations requester_disabled() {
  return {Setup::Disabled, with(with(disabled_commands(), {
      both(E::Enable, S::Ready, N::Enabled),
      both(E::SeenNotReady, S::NotReady, N::None, R::InterfaceDisabled),
      both(E::SeenReady, S::NotReady, N::None),
      both(E::SeenActive, S::NotReady, N::None, R::InterfaceDisabled),
      both(E::SeenComplete, S::NotReady, N::None, R::InterfaceDisabled),
      both(E::SeenFail, S::NotReady, N::CounterpartFailed, R::InterfaceDisabled),
  }), idle_timers(S::NotReady))};
}

// DISABLED while the response went FAIL: on ENABLED the request must
// acknowledge that FAIL (Table 5 condition 2) under 1.6.
SetupExpectations requester_disabled_fail_pending() {
  return {Setup::DisabledFailPending, with(with(disabled_commands(), {
      differ(E::Enable, S::Fail, N::CounterpartFailed, R::CounterpartFail,
             S::Ready, N::Enabled, R::None),
      both(E::SeenNotReady, S::NotReady, N::None, R::InterfaceDisabled),
      both(E::SeenReady, S::NotReady, N::None, R::InterfaceDisabled),
      both(E::SeenActive, S::NotReady, N::None, R::InterfaceDisabled),
      both(E::SeenComplete, S::NotReady, N::None, R::InterfaceDisabled),
      both(E::SeenFail, S::NotReady, N::None),
  }), idle_timers(S::NotReady))};
}

std::vector<SetupExpectations> requester_expectations() {
  return {
      requester_ready(),
      requester_not_ready(),
      requester_active(),
      requester_active_engaged(),
      requester_fail(),
      requester_fail_acknowledged(),
      requester_disabled(),
      requester_disabled_fail_pending(),
  };
}

// clang-format on

const std::vector<SetupExpectations>& expectations() {
  static const std::vector<SetupExpectations> all = requester_expectations();
  return all;
}

class RequesterTable : public ::testing::TestWithParam<TableCase> {};

TEST_P(RequesterTable, EveryEventMatchesTheSpec) {
  check_every_event(expectations()[GetParam().setup_index], GetParam().profile, Role::Requester,
                    requester_in, [](const Requester&, const StepResult&) {});
}

INSTANTIATE_TEST_SUITE_P(Pairs, RequesterTable,
                         ::testing::ValuesIn(table_cases(expectations().size())),
                         [](const ::testing::TestParamInfo<TableCase>& param_info) {
                           return table_case_name(param_info.param, expectations());
                         });

TEST(RequesterTable, SetupsReachEveryPhaseOfTheRole) {
  std::set<Phase> reached;
  for (const auto& setup : expectations()) {
    reached.insert(requester_in(setup.setup, Profile::V1_6).phase());
  }
  EXPECT_EQ(reached, (std::set<Phase>{Phase::NotReady, Phase::Ready, Phase::Active, Phase::Fail,
                                      Phase::Disabled}));
}

TEST(RequesterTable, NeverReachesComplete) {
  for (const auto& row : requester_table()) {
    EXPECT_NE(row.to, Target::Complete) << "Table 5 has no COMPLETE request state";
  }
}

}  // namespace
}  // namespace mtc::core::testing_support
