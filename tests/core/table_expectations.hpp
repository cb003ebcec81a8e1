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
constexpr Expect differ(Event e, InteractionState s16, Notice n16, Reason r16,
                        InteractionState s13, Notice n13, Reason r13) {
  return Expect{e, s16, n16, r16, s13, n13, r13};
}

struct SetupExpectations {
  Setup setup;
  std::vector<Expect> rows;
};

}  // namespace mtc::core::testing_support
