// Log spellings of the machine vocabulary. Indexed by enumerator value, so
// each array lists the enumerators in declaration order.
#include "mtc/core/result.hpp"

#include <array>
#include <cstddef>

#include "mtc/core/transition.hpp"

namespace mtc::core {
namespace {

template <typename Enum, std::size_t N>
constexpr std::string_view lookup(const std::array<std::string_view, N>& names, Enum e) noexcept {
  const auto i = static_cast<std::size_t>(e);
  return i < N ? names[i] : std::string_view{"?"};
}

constexpr std::array<std::string_view, kEventCount> kEvents{"Request",
                                                            "Accept",
                                                            "Complete",
                                                            "Fail",
                                                            "RecoverReady",
                                                            "RecoverNotReady",
                                                            "SetReady",
                                                            "SetNotReady",
                                                            "Disable",
                                                            "Enable",
                                                            "Reevaluate",
                                                            "SeenNotReady",
                                                            "SeenReady",
                                                            "SeenActive",
                                                            "SeenComplete",
                                                            "SeenFail",
                                                            "SeenUnavailable",
                                                            "SeenInvalid",
                                                            "ResponseTimeout",
                                                            "ServiceTimeout",
                                                            "CompletionAckTimeout",
                                                            "FailAckTimeout",
                                                            "FailResetTimeout"};

constexpr std::array<std::string_view, 18> kNotices{
    "None",      "RequestIssued",     "RequestObserved",
    "Accepted",  "Completed",         "Acknowledged",
    "Failed",    "CounterpartFailed", "FailAcknowledged",
    "Recovered", "TimedOut",          "ProtocolViolation",
    "Rejected",  "ReadinessChanged",  "Disabled",
    "Enabled",   "CommsLost",         "CommsRestored"};

struct ReasonText {
  std::string_view id;
  std::string_view sentence;
};

constexpr std::array<ReasonText, 29> kReasons{{
    {"None", ""},
    {"Application", "the application reported a failure"},
    {"CounterpartFail", "the counterpart went FAIL"},
    {"CounterpartLeftActive", "the counterpart left ACTIVE before COMPLETE"},
    {"CounterpartNotReady", "the responder went NOT_READY while the request was ACTIVE"},
    {"CommsLost", "the counterpart became UNAVAILABLE or stopped sending heartbeats"},
    {"ResponseTimeout", "the responder did not go ACTIVE in time"},
    {"ServiceTimeout", "the service did not complete in time"},
    {"CompletionAckTimeout", "the requester did not acknowledge COMPLETE in time"},
    {"FailAckTimeout", "the counterpart did not acknowledge FAIL in time"},
    {"FailResetTimeout", "FAIL timed out back to READY (1.3)"},
    {"UnknownValue", "the counterpart reported a value outside the vocabulary"},
    {"CompleteOnRequest", "a REQUEST reported COMPLETE, which Table 5 does not allow"},
    {"ActiveWithoutRequest", "the response went ACTIVE while the request was not ACTIVE"},
    {"CompleteWithoutRequest", "the response went COMPLETE while the request was not ACTIVE"},
    {"CompleteWithoutActive", "the response went COMPLETE without having been ACTIVE"},
    {"WrongRole", "the command belongs to the other role"},
    {"NotReady", "this side is NOT_READY"},
    {"NotIdle", "only allowed in READY or NOT_READY"},
    {"NotActive", "only allowed in ACTIVE"},
    {"NotFailed", "only allowed in FAIL"},
    {"AlreadyActive", "already ACTIVE"},
    {"AlreadyFailed", "already in FAIL"},
    {"FailNotAcknowledged", "the counterpart has not acknowledged FAIL yet"},
    {"RequestNotActive", "the request is not ACTIVE"},
    {"CounterpartBusy", "the response is not READY"},
    {"InterfaceDisabled", "INTERFACE_STATE is DISABLED"},
    {"PreconditionNotMet", "the equipment's precondition does not allow it (e.g. door state)"},
    {"InvalidTarget", "recovery must go to READY or NOT_READY"},
}};

constexpr std::array<std::string_view, 7> kPhases{"NotReady", "Ready",    "Active", "Complete",
                                                  "Fail",     "Disabled", "Any"};
constexpr std::array<std::string_view, 16> kGuards{"Always",
                                                   "V13",
                                                   "V16",
                                                   "Permitted",
                                                   "NotPermitted",
                                                   "WantsReady",
                                                   "CounterpartReady",
                                                   "CounterpartNotReady",
                                                   "CounterpartEngaged",
                                                   "CounterpartNotEngaged",
                                                   "RequestActive",
                                                   "RequestNotActive",
                                                   "AcknowledgesFail",
                                                   "Acknowledged",
                                                   "NotAcknowledged",
                                                   "CounterpartFailPending"};
constexpr std::array<std::string_view, 8> kTargets{"Stay",     "NotReady", "Ready", "Active",
                                                   "Complete", "Fail",     "Idle",  "Disabled"};

static_assert(static_cast<std::size_t>(Notice::CommsRestored) + 1 == kNotices.size());
static_assert(static_cast<std::size_t>(Reason::InvalidTarget) + 1 == kReasons.size());
static_assert(static_cast<std::size_t>(Event::FailResetTimeout) + 1 == kEventCount);
static_assert(static_cast<std::size_t>(Guard::CounterpartFailPending) + 1 == kGuards.size());
static_assert(static_cast<std::size_t>(Target::Disabled) + 1 == kTargets.size());

}  // namespace

std::string_view to_string(Event e) noexcept {
  return lookup(kEvents, e);
}
std::string_view to_string(Notice n) noexcept {
  return lookup(kNotices, n);
}
std::string_view to_string(Reason r) noexcept {
  const auto i = static_cast<std::size_t>(r);
  return i < kReasons.size() ? kReasons[i].id : std::string_view{"?"};
}
std::string_view describe(Reason r) noexcept {
  const auto i = static_cast<std::size_t>(r);
  return i < kReasons.size() ? kReasons[i].sentence : std::string_view{"unknown reason"};
}
std::string_view to_string(Phase p) noexcept {
  return lookup(kPhases, p);
}
std::string_view to_string(Guard g) noexcept {
  return lookup(kGuards, g);
}
std::string_view to_string(Target t) noexcept {
  return lookup(kTargets, t);
}

}  // namespace mtc::core
