// Observed states are core enums tagged with their item kind; text exists
// only where they are printed, and a number outside the vocabulary stays
// distinguishable from every known state.
#include <gtest/gtest.h>

#include "mtc/core/observation.hpp"

namespace mtc::core {
namespace {

TEST(ObservedState, DefaultIsAnUnavailableInteractionItem) {
  const ObservedState s;
  EXPECT_EQ(s.kind(), ItemKind::Interaction);
  EXPECT_TRUE(s.in_vocabulary());
  EXPECT_TRUE(s.unavailable());
  EXPECT_EQ(s.interaction(), InteractionState::Unavailable);
  EXPECT_EQ(to_string(s), "UNAVAILABLE");
}

TEST(ObservedState, EachEnumSetsItsKindAndOnlyItsAccessor) {
  const ObservedState ready = InteractionState::Ready;
  const ObservedState enabled = InterfaceState::Enabled;
  const ObservedState open_door = DoorState::Open;
  const ObservedState closed_chuck = ChuckState::Closed;
  EXPECT_EQ(ready.kind(), ItemKind::Interaction);
  EXPECT_EQ(enabled.kind(), ItemKind::InterfaceState);
  EXPECT_EQ(open_door.kind(), ItemKind::DoorState);
  EXPECT_EQ(closed_chuck.kind(), ItemKind::ChuckState);
  EXPECT_EQ(ready.interaction(), InteractionState::Ready);
  EXPECT_FALSE(ready.interface_state().has_value());
  EXPECT_EQ(enabled.interface_state(), InterfaceState::Enabled);
  EXPECT_FALSE(enabled.interaction().has_value());
  EXPECT_EQ(open_door.door(), DoorState::Open);
  EXPECT_FALSE(open_door.chuck().has_value());
  EXPECT_EQ(closed_chuck.chuck(), ChuckState::Closed);
  EXPECT_FALSE(closed_chuck.door().has_value());
}

TEST(ObservedState, SameEnumeratorOfAnotherKindIsAnotherState) {
  // DOOR_STATE and CHUCK_STATE share spellings, not identity.
  EXPECT_NE(ObservedState(DoorState::Open), ObservedState(ChuckState::Open));
  EXPECT_NE(ObservedState(InteractionState::Unavailable),
            ObservedState(InterfaceState::Unavailable));
  EXPECT_EQ(ObservedState(DoorState::Open), ObservedState(DoorState::Open));
}

TEST(ObservedState, PrintsTheMtconnectSpellingOfEveryKind) {
  for (auto s : kAllInteractionStates) EXPECT_EQ(to_string(ObservedState(s)), to_string(s));
  EXPECT_EQ(to_string(ObservedState(InterfaceState::Disabled)), "DISABLED");
  EXPECT_EQ(to_string(ObservedState(DoorState::Unlatched)), "UNLATCHED");
  EXPECT_EQ(to_string(ObservedState(ChuckState::Closed)), "CLOSED");
}

TEST(ObservedState, ValueOutsideTheVocabularyStaysDistinguishable) {
  const auto odd = ObservedState::outside_vocabulary(ItemKind::InterfaceState, 7);
  EXPECT_FALSE(odd.in_vocabulary());
  EXPECT_EQ(odd.kind(), ItemKind::InterfaceState);
  EXPECT_EQ(odd.raw(), 7);
  EXPECT_FALSE(odd.interface_state().has_value());
  EXPECT_FALSE(odd.unavailable());
  // Not confused with the known state that happens to have the same number.
  const auto zero = ObservedState::outside_vocabulary(ItemKind::InterfaceState, 0);
  EXPECT_NE(zero, ObservedState(InterfaceState::Unavailable));
  EXPECT_FALSE(zero.unavailable());
  EXPECT_EQ(to_string(odd), "INVALID(7)");
}

TEST(ObservedValue, KindFollowsItsState) {
  ObservedValue v;
  EXPECT_EQ(v.kind(), ItemKind::Interaction);
  v.state = DoorState::Closed;
  EXPECT_EQ(v.kind(), ItemKind::DoorState);
}

}  // namespace
}  // namespace mtc::core
