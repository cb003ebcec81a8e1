// The vendor API's transport defaults (issue 10): a program that does not
// choose reaches the other machines of its cell over Fast DDS's builtin
// transports; loopback is chosen explicitly. No DDS entity is created here.
#include <gtest/gtest.h>

#include "mtc/dds/domain_observer.hpp"
#include "mtc/dds/equipment.hpp"
#include "mtc/qos/participant.hpp"

namespace mtc::dds {
namespace {

TEST(TransportDefaults, EquipmentAndObserverDefaultToTheNetwork) {
  // transport-guard: the defaults themselves are under test
  const EquipmentOptions equipment;
  // transport-guard: the defaults themselves are under test
  const DomainObserverOptions observer;
  // transport-guard: the defaults themselves are under test
  const qos::ParticipantConfig participant;
  EXPECT_EQ(equipment.transport, qos::Transport::Network);
  EXPECT_EQ(observer.transport, qos::Transport::Network);
  EXPECT_EQ(participant.transport, qos::Transport::Network);
}

}  // namespace
}  // namespace mtc::dds
