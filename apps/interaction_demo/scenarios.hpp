// The demo's scripts: Table 1 and the failure scenarios of Part 5 section 5.1.
#pragma once

#include <array>

#include "mtc/core/profile.hpp"

namespace mtc::demo {

struct Scenario {
  int number;  // 0 = success run, 1-6 = section 5.1, 7 = time limits
  const char* title;
  const char* summary;  // what the text says happens
  bool differs_in_1_3;  // worth replaying under the 1.3 profile
  void (*run)(core::Profile profile);
};

const std::array<Scenario, 8>& scenarios();

}  // namespace mtc::demo
