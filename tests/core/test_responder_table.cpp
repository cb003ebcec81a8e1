// Every (state, event) pair of the responder machine (Table 6), under the
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

std::vector<Expect> with(std::vector<Expect> rows, const std::vector<Expect>& more) {
  rows.insert(rows.end(), more.begin(), more.end());
  return rows;
}

std::vector<Expect> quiet_timers(S s) {
  return {both(E::ResponseTimeout, s, N::None), both(E::ServiceTimeout, s, N::None),
          both(E::CompletionAckTimeout, s, N::None), both(E::FailAckTimeout, s, N::None),
          both(E::FailResetTimeout, s, N::None)};
}

// Commands and observations with the same outcome in READY whether or not
// the request is ACTIVE.
std::vector<Expect> ready_common() {
  return {
      both(E::Request, S::Ready, N::Rejected, R::WrongRole),
      both(E::Complete, S::Ready, N::Rejected, R::NotActive),
      both(E::Fail, S::Fail, N::Failed, R::Application),
      both(E::RecoverReady, S::Ready, N::Rejected, R::NotFailed),
      both(E::RecoverNotReady, S::Ready, N::Rejected, R::NotFailed),
      both(E::SetReady, S::Ready, N::None),
      // Table 6 READY: "If the Responder is not ready ... MUST transition to NOT_READY".
      both(E::SetNotReady, S::NotReady, N::ReadinessChanged, R::Application),
      both(E::Disable, S::NotReady, N::Disabled, R::InterfaceDisabled),
      both(E::Enable, S::Ready, N::None),
      both(E::Reevaluate, S::Ready, N::None),
      // A REQUEST has no COMPLETE (Table 5).
      both(E::SeenComplete, S::Fail, N::ProtocolViolation, R::CompleteOnRequest),
      // Table 6 condition 2 (both editions).
      both(E::SeenFail, S::Fail, N::CounterpartFailed, R::CounterpartFail),
      differ(E::SeenUnavailable, S::Fail, N::CommsLost, R::CommsLost, S::Ready, N::CommsLost,
             R::CommsLost),
      both(E::SeenInvalid, S::Fail, N::ProtocolViolation, R::UnknownValue),
  };
}

// clang-format off
// DISABLED (Table 3): NOT_READY, every command refused.
std::vector<Expect> disabled_commands() {
  return {
      both(E::Request, S::NotReady, N::Rejected, R::WrongRole),
      both(E::Accept, S::NotReady, N::Rejected, R::InterfaceDisabled),
      both(E::Complete, S::NotReady, N::Rejected, R::InterfaceDisabled),
      both(E::Fail, S::NotReady, N::Rejected, R::InterfaceDisabled),
      both(E::RecoverReady, S::NotReady, N::Rejected, R::InterfaceDisabled),
      both(E::RecoverNotReady, S::NotReady, N::Rejected, R::InterfaceDisabled),
      both(E::SetReady, S::NotReady, N::Rejected, R::InterfaceDisabled),
      both(E::SetNotReady, S::NotReady, N::Rejected, R::InterfaceDisabled),
      both(E::Disable, S::NotReady, N::None),
      both(E::Reevaluate, S::NotReady, N::None),
      both(E::SeenComplete, S::NotReady, N::ProtocolViolation, R::CompleteOnRequest),
      both(E::SeenUnavailable, S::NotReady, N::CommsLost, R::CommsLost),
      both(E::SeenInvalid, S::NotReady, N::ProtocolViolation, R::UnknownValue),
  };
}

// READY, request READY.
SetupExpectations responder_ready() {
  return {Setup::Ready, with(with(ready_common(), {
      // Table 6 ACTIVE: MUST NOT go ACTIVE unless the request is ACTIVE.
      both(E::Accept, S::Ready, N::Rejected, R::RequestNotActive),
      both(E::SeenNotReady, S::Ready, N::None),
      both(E::SeenReady, S::Ready, N::None),
      both(E::SeenActive, S::Ready, N::RequestObserved),  // Table 1 step 2
  }), quiet_timers(S::Ready))};
}

// READY, request ACTIVE (step 2 done, waiting for the application).
SetupExpectations responder_ready_request_active() {
  return {Setup::ResponderReadyRequestActive, with(with(ready_common(), {
      both(E::Accept, S::Active, N::Accepted),  // step 3
      both(E::SeenNotReady, S::Ready, N::None),
      both(E::SeenReady, S::Ready, N::None),
      both(E::SeenActive, S::Ready, N::None),
  }), quiet_timers(S::Ready))};
}

// NOT_READY by the application's wish, request READY.
SetupExpectations responder_not_ready() {
  return {Setup::NotReady, with({
      both(E::Request, S::NotReady, N::Rejected, R::WrongRole),
      both(E::Accept, S::NotReady, N::Rejected, R::NotReady),
      both(E::Complete, S::NotReady, N::Rejected, R::NotActive),
      both(E::Fail, S::Fail, N::Failed, R::Application),
      both(E::RecoverReady, S::NotReady, N::Rejected, R::NotFailed),
      both(E::RecoverNotReady, S::NotReady, N::Rejected, R::NotFailed),
      both(E::SetReady, S::Ready, N::ReadinessChanged, R::Application),
      both(E::SetNotReady, S::NotReady, N::None),
      both(E::Disable, S::NotReady, N::Disabled, R::InterfaceDisabled),
      both(E::Enable, S::NotReady, N::None),
      both(E::Reevaluate, S::NotReady, N::None),
      both(E::SeenNotReady, S::NotReady, N::None),
      both(E::SeenReady, S::NotReady, N::None),
      // Reported so the application knows the request is being ignored.
      both(E::SeenActive, S::NotReady, N::RequestObserved, R::NotReady),
      both(E::SeenComplete, S::Fail, N::ProtocolViolation, R::CompleteOnRequest),
      both(E::SeenFail, S::Fail, N::CounterpartFailed, R::CounterpartFail),
      differ(E::SeenUnavailable, S::Fail, N::CommsLost, R::CommsLost,
             S::NotReady, N::CommsLost, R::CommsLost),
      both(E::SeenInvalid, S::Fail, N::ProtocolViolation, R::UnknownValue),
  }, quiet_timers(S::NotReady))};
}

// ACTIVE, request ACTIVE: performing the service.
SetupExpectations responder_active() {
  return {Setup::Active, {
      both(E::Request, S::Active, N::Rejected, R::WrongRole),
      both(E::Accept, S::Active, N::Rejected, R::AlreadyActive),
      both(E::Complete, S::Complete, N::Completed),  // step 4
      both(E::Fail, S::Fail, N::Failed, R::Application),  // scenario 2
      both(E::RecoverReady, S::Active, N::Rejected, R::NotFailed),
      both(E::RecoverNotReady, S::Active, N::Rejected, R::NotFailed),
      both(E::SetReady, S::Active, N::Rejected, R::NotIdle),
      both(E::SetNotReady, S::Active, N::Rejected, R::NotIdle),
      both(E::Disable, S::NotReady, N::Disabled, R::InterfaceDisabled),
      both(E::Enable, S::Active, N::None),
      both(E::Reevaluate, S::Active, N::None),
      // Scenario 4 and its NOT_READY note; 1.3 device with no FAIL state.
      both(E::SeenNotReady, S::Fail, N::CounterpartFailed, R::CounterpartLeftActive),
      both(E::SeenReady, S::Fail, N::CounterpartFailed, R::CounterpartLeftActive),
      both(E::SeenActive, S::Active, N::None),
      both(E::SeenComplete, S::Fail, N::ProtocolViolation, R::CompleteOnRequest),
      both(E::SeenFail, S::Fail, N::CounterpartFailed, R::CounterpartFail),  // scenario 3
      both(E::SeenUnavailable, S::Fail, N::CommsLost, R::CommsLost),      // scenario 6
      both(E::SeenInvalid, S::Fail, N::ProtocolViolation, R::UnknownValue),
      both(E::ResponseTimeout, S::Active, N::None),
      both(E::ServiceTimeout, S::Fail, N::TimedOut, R::ServiceTimeout),
      both(E::CompletionAckTimeout, S::Active, N::None),
      both(E::FailAckTimeout, S::Active, N::None),
      both(E::FailResetTimeout, S::Active, N::None),
  }};
}

// COMPLETE, request still ACTIVE.
SetupExpectations responder_complete() {
  return {Setup::Complete, {
      both(E::Request, S::Complete, N::Rejected, R::WrongRole),
      both(E::Accept, S::Complete, N::Rejected, R::NotIdle),
      both(E::Complete, S::Complete, N::Rejected, R::NotActive),
      both(E::Fail, S::Fail, N::Failed, R::Application),
      both(E::RecoverReady, S::Complete, N::Rejected, R::NotFailed),
      both(E::RecoverNotReady, S::Complete, N::Rejected, R::NotFailed),
      // MUST remain COMPLETE until the request acknowledges.
      both(E::SetReady, S::Complete, N::None),
      both(E::SetNotReady, S::Complete, N::None),
      both(E::Disable, S::NotReady, N::Disabled, R::InterfaceDisabled),
      both(E::Enable, S::Complete, N::None),
      both(E::Reevaluate, S::Complete, N::None),
      both(E::SeenNotReady, S::Ready, N::Acknowledged),
      both(E::SeenReady, S::Ready, N::Acknowledged),  // steps 7-8
      both(E::SeenActive, S::Complete, N::None),
      both(E::SeenComplete, S::Fail, N::ProtocolViolation, R::CompleteOnRequest),
      both(E::SeenFail, S::Fail, N::CounterpartFailed, R::CounterpartFail),
      both(E::SeenUnavailable, S::Fail, N::CommsLost, R::CommsLost),
      both(E::SeenInvalid, S::Fail, N::ProtocolViolation, R::UnknownValue),
      both(E::ResponseTimeout, S::Complete, N::None),
      both(E::ServiceTimeout, S::Complete, N::None),
      both(E::CompletionAckTimeout, S::Complete, N::TimedOut, R::CompletionAckTimeout),
      both(E::FailAckTimeout, S::Complete, N::None),
      both(E::FailResetTimeout, S::Complete, N::None),
  }};
}

// FAIL by own failure, request READY. Under 1.3 a request out of ACTIVE
// already acknowledges the response's FAIL.
SetupExpectations responder_fail() {
  return {Setup::Fail, {
      both(E::Request, S::Fail, N::Rejected, R::WrongRole),
      both(E::Accept, S::Fail, N::Rejected, R::AlreadyFailed),
      both(E::Complete, S::Fail, N::Rejected, R::NotActive),
      both(E::Fail, S::Fail, N::Rejected, R::AlreadyFailed),
      differ(E::RecoverReady, S::Fail, N::Rejected, R::FailNotAcknowledged,
             S::Ready, N::Recovered, R::None),
      differ(E::RecoverNotReady, S::Fail, N::Rejected, R::FailNotAcknowledged,
             S::NotReady, N::Recovered, R::None),
      both(E::SetReady, S::Fail, N::Rejected, R::NotIdle),
      both(E::SetNotReady, S::Fail, N::Rejected, R::NotIdle),
      both(E::Disable, S::NotReady, N::Disabled, R::InterfaceDisabled),
      both(E::Enable, S::Fail, N::None),
      both(E::Reevaluate, S::Fail, N::None),
      both(E::SeenNotReady, S::Fail, N::None),
      both(E::SeenReady, S::Fail, N::None),
      both(E::SeenActive, S::Fail, N::None),
      both(E::SeenComplete, S::Fail, N::ProtocolViolation, R::CompleteOnRequest),
      differ(E::SeenFail, S::Fail, N::FailAcknowledged, R::None, S::Fail, N::None, R::None),
      both(E::SeenUnavailable, S::Fail, N::CommsLost, R::CommsLost),
      both(E::SeenInvalid, S::Fail, N::ProtocolViolation, R::UnknownValue),
      both(E::ResponseTimeout, S::Fail, N::None),
      both(E::ServiceTimeout, S::Fail, N::None),
      both(E::CompletionAckTimeout, S::Fail, N::None),
      differ(E::FailAckTimeout, S::Fail, N::TimedOut, R::FailAckTimeout, S::Fail, N::None,
             R::None),
      differ(E::FailResetTimeout, S::Fail, N::None, R::None,
             S::Ready, N::Recovered, R::FailResetTimeout),
  }};
}

// FAIL, request FAIL: acknowledged (both editions).
SetupExpectations responder_fail_acknowledged() {
  return {Setup::FailAcknowledged, {
      both(E::Request, S::Fail, N::Rejected, R::WrongRole),
      both(E::Accept, S::Fail, N::Rejected, R::AlreadyFailed),
      both(E::Complete, S::Fail, N::Rejected, R::NotActive),
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
      both(E::SeenComplete, S::Fail, N::ProtocolViolation, R::CompleteOnRequest),
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

SetupExpectations responder_disabled() {
  return {Setup::Disabled, with(with(disabled_commands(), {
      both(E::Enable, S::Ready, N::Enabled),
      both(E::SeenNotReady, S::NotReady, N::None, R::InterfaceDisabled),
      both(E::SeenReady, S::NotReady, N::None),
      both(E::SeenActive, S::NotReady, N::None, R::InterfaceDisabled),
      both(E::SeenFail, S::NotReady, N::CounterpartFailed, R::InterfaceDisabled),
  }), quiet_timers(S::NotReady))};
}

// The request went FAIL while DISABLED: ENABLED acknowledges it (both
// editions: Table 6 condition 2, 1.3 "the response will fail as well").
SetupExpectations responder_disabled_fail_pending() {
  return {Setup::DisabledFailPending, with(with(disabled_commands(), {
      both(E::Enable, S::Fail, N::CounterpartFailed, R::CounterpartFail),
      both(E::SeenNotReady, S::NotReady, N::None, R::InterfaceDisabled),
      both(E::SeenReady, S::NotReady, N::None, R::InterfaceDisabled),
      both(E::SeenActive, S::NotReady, N::None, R::InterfaceDisabled),
      both(E::SeenFail, S::NotReady, N::None),
  }), quiet_timers(S::NotReady))};
}

std::vector<SetupExpectations> responder_expectations() {
  return {
      responder_ready(),
      responder_ready_request_active(),
      responder_not_ready(),
      responder_active(),
      responder_complete(),
      responder_fail(),
      responder_fail_acknowledged(),
      responder_disabled(),
      responder_disabled_fail_pending(),
  };
}

// clang-format on

const std::vector<SetupExpectations>& expectations() {
  static const std::vector<SetupExpectations> all = responder_expectations();
  return all;
}

class ResponderTable : public ::testing::TestWithParam<TableCase> {};

TEST_P(ResponderTable, EveryEventMatchesTheSpec) {
  check_every_event(expectations()[GetParam().setup_index], GetParam().profile, Role::Responder,
                    responder_in, [](const Responder& m, const StepResult& r) {
                      // Table 6: never ACTIVE unless the request is ACTIVE.
                      if (r.changed() && r.current == InteractionState::Active) {
                        EXPECT_EQ(m.counterpart(), InteractionState::Active);
                      }
                    });
}

INSTANTIATE_TEST_SUITE_P(Pairs, ResponderTable,
                         ::testing::ValuesIn(table_cases(expectations().size())),
                         [](const ::testing::TestParamInfo<TableCase>& param_info) {
                           return table_case_name(param_info.param, expectations());
                         });

TEST(ResponderTable, SetupsReachEveryPhaseOfTheRole) {
  std::set<Phase> reached;
  for (const auto& setup : expectations()) {
    reached.insert(responder_in(setup.setup, Profile::V1_6).phase());
  }
  EXPECT_EQ(reached, (std::set<Phase>{Phase::NotReady, Phase::Ready, Phase::Active, Phase::Complete,
                                      Phase::Fail, Phase::Disabled}));
}

TEST(ResponderTable, OnlyAcceptLeadsFromReadyToActive) {
  for (const auto& row : responder_table()) {
    if (row.to == Target::Active) {
      EXPECT_EQ(row.event, Event::Accept);
      EXPECT_EQ(row.from, Phase::Ready);
    }
  }
}

}  // namespace
}  // namespace mtc::core::testing_support
