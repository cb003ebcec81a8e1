// Links mtc::dds alone, as a vendor does: its errors carry the project's own
// codes. Equipment is referenced so the runtime is linked, but not created
// (that would start DDS traffic).
#include <iostream>
#include <memory>

#include "mtc/dds/equipment.hpp"
#include "mtc/dds/error.hpp"

int main(int argc, char**) {
  if (argc > 1) {  // never taken in the test: only makes the linker resolve Equipment
    // transport-guard: never created, so never on any transport
    const auto equipment = std::make_unique<mtc::dds::Equipment>(mtc::dds::EquipmentOptions{});
    return 2;
  }
  const mtc::dds::ConfigError error("no such interface");
  std::cout << "mtc::dds: " << error.what() << "\n";
  return error.code() == mtc::dds::ErrorCode::InvalidConfiguration ? 0 : 1;
}
