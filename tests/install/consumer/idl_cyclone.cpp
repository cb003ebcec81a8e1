// Links mtc::idl_cyclone alone: idlc's descriptor of a topic type carries the
// type name and key count that Fast DDS's side of the wire expects.
#include <cstring>
#include <iostream>

#include "mtc/idl_cyclone/mtconnect_interfaces.h"

int main() {
  const auto& desc = mtc_idl_InteractionSample_desc;
  const bool ok =
      std::strcmp(desc.m_typename, "mtc::idl::InteractionSample") == 0 && desc.m_nkeys == 2;
  std::cout << "mtc::idl_cyclone: " << desc.m_typename << ", " << desc.m_nkeys << " keys "
            << (ok ? "as expected" : "WRONG") << "\n";
  return ok ? 0 : 1;
}
