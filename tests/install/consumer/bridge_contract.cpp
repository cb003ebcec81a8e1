// Links mtc::bridge_contract alone: a request target is split into decoded
// path segments and query parameters.
#include <iostream>
#include <string>

#include "mtc/bridge/request.hpp"

int main() {
  std::string error;
  const auto target = mtc::bridge::parse_target("/mill/sample?from=10&count=5", error);
  if (!target) {
    std::cerr << error << "\n";
    return 1;
  }
  std::cout << "mtc::bridge_contract: " << target->segments.size() << " segments, "
            << target->query.size() << " parameters\n";
  return target->segments.size() == 2 && target->query.size() == 2 ? 0 : 1;
}
