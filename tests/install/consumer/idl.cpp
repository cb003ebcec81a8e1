// Links mtc::idl alone: the instance handle of a sample is the RTPS hash of
// its key fields, the same for equal keys and different for others.
#include <iostream>

#include "mtc/idl/mtconnect_interfacesPubSubTypes.h"
#include "mtc/idl/type_support.hpp"

namespace {

eprosima::fastrtps::rtps::InstanceHandle_t handle_of(const char* device, const char* item) {
  mtc::idl::InteractionSample sample;
  sample.device_uuid(device);
  sample.data_item_id(item);
  eprosima::fastrtps::rtps::InstanceHandle_t handle;
  mtc::idl::compute_key_hash(sample, handle, false);
  return handle;
}

}  // namespace

int main() {
  const auto a = handle_of("cnc-1", "mh1_material_load_request");
  const auto again = handle_of("cnc-1", "mh1_material_load_request");
  const auto other = handle_of("robot-1", "mh1_material_load_request");
  std::cout << "mtc::idl: key hash " << (a == again && a != other ? "stable" : "WRONG") << "\n";
  return a == again && a != other ? 0 : 1;
}
