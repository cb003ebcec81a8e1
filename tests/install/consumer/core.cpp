// Links mtc::core alone: an MTConnect spelling round-trips through the
// vocabulary.
#include <iostream>

#include "mtc/core/vocabulary.hpp"

int main() {
  const auto text = mtc::core::to_string(mtc::core::Service::MaterialLoad);
  const auto back = mtc::core::parse_service(text);
  std::cout << "mtc::core: " << text << "\n";
  return text == "MATERIAL_LOAD" && back == mtc::core::Service::MaterialLoad ? 0 : 1;
}
