// Expectation rows for the exhaustive (state, event) tests, written from the
// text of Tables 5/6 and section 5.1 (1.6/1.8) and section 3 of 1.3, not
// generated from the implementation.
#pragma once

#include <gtest/gtest.h>

#include <ostream>
#include <set>
#include <string>
#include <vector>

#include "machine_fixtures.hpp"

namespace mtc::core::testing_support {

struct Expect {
  Event event;
  InteractionState state16;
  Notice notice16;
  Reason reason16;
  InteractionState state13;
  Notice notice13;
  Reason reason13;
};

// Same outcome under both profiles.
constexpr Expect both(Event e, InteractionState s, Notice n, Reason r = Reason::None) {
  return Expect{e, s, n, r, s, n, r};
}
// 1.6/1.8 outcome first, then the 1.3 outcome.
constexpr Expect differ(Event e, InteractionState s16, Notice n16, Reason r16, InteractionState s13,
                        Notice n13, Reason r13) {
  return Expect{e, s16, n16, r16, s13, n13, r13};
}

struct SetupExpectations {
  Setup setup;
  std::vector<Expect> rows;
};

// One parameter of the exhaustive tests: a profile and a starting setup.
struct TableCase {
  Profile profile;
  std::size_t setup_index;
};

// What gtest lists for the parameter: a stable name, not a byte dump.
inline void PrintTo(const TableCase& c, std::ostream* os) {
  *os << (c.profile == Profile::V1_3 ? "V1_3" : "V1_6") << " setup " << c.setup_index;
}

inline std::vector<TableCase> table_cases(std::size_t setups) {
  std::vector<TableCase> cases;
  for (const auto p : {Profile::V1_6, Profile::V1_3}) {
    for (std::size_t i = 0; i < setups; ++i) cases.push_back({p, i});
  }
  return cases;
}

// Applies every row of one starting setup to a fresh machine from
// `make_machine(setup, profile)` and checks the outcome the row expects; then
// `role_check(machine, result)` asserts what only that role must hold. Shared
// by the requester and responder tables so both are checked the same way.
template <typename MakeMachine, typename RoleCheck>
void check_every_event(const SetupExpectations& setup, Profile profile, Role role,
                       MakeMachine make_machine, RoleCheck role_check) {
  const bool v13 = profile == Profile::V1_3;
  std::set<Event> covered;
  for (const Expect& x : setup.rows) {
    covered.insert(x.event);
    auto m = make_machine(setup.setup, profile);
    const InteractionState before = m.state();
    const StepResult r = m.step(x.event, kT0);
    SCOPED_TRACE(::testing::Message() << "from " << setup_name(setup.setup) << " event " << x.event
                                      << (v13 ? " (1.3)" : " (1.6)"));
    EXPECT_EQ(r.previous, before);
    EXPECT_EQ(r.current, v13 ? x.state13 : x.state16);
    EXPECT_EQ(m.state(), r.current);
    EXPECT_EQ(r.notice, v13 ? x.notice13 : x.notice16);
    EXPECT_EQ(r.reason, v13 ? x.reason13 : x.reason16);
    EXPECT_EQ(r.event, x.event);
    EXPECT_EQ(r.role, role);
    if (r.rejected()) {
      EXPECT_FALSE(r.changed()) << "a rejection must not change state";
    }
    role_check(m, r);
  }
  EXPECT_EQ(covered.size(), kEventCount) << setup_name(setup.setup) << " does not list every event";
}

// Test name of one parameter: profile and starting setup.
inline std::string table_case_name(const TableCase& c, const std::vector<SetupExpectations>& all) {
  return std::string(c.profile == Profile::V1_3 ? "V1_3_" : "V1_6_") +
         setup_name(all[c.setup_index].setup);
}

}  // namespace mtc::core::testing_support
