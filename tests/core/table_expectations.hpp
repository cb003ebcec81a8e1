// Expectation rows for the exhaustive (state, event) tests, written from the
// text of Tables 5/6 and section 5.1 (1.6/1.8) and section 3 of 1.3, not
// generated from the implementation.
#pragma once

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

inline std::vector<TableCase> table_cases(std::size_t setups) {
  std::vector<TableCase> cases;
  for (const auto p : {Profile::V1_6, Profile::V1_3}) {
    for (std::size_t i = 0; i < setups; ++i) cases.push_back({p, i});
  }
  return cases;
}

}  // namespace mtc::core::testing_support
