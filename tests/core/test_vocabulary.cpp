// Round trips of every MTConnect spelling, and rejection of anything else.
#include <gtest/gtest.h>

#include <string>

#include "mtc/core/result.hpp"
#include "mtc/core/transition.hpp"
#include "mtc/core/vocabulary.hpp"

namespace mtc::core {
namespace {

TEST(Vocabulary, InteractionStatesRoundTrip) {
  for (const auto s : kAllInteractionStates) {
    const auto parsed = parse_interaction_state(to_string(s));
    ASSERT_TRUE(parsed.has_value()) << to_string(s);
    EXPECT_EQ(*parsed, s);
  }
  EXPECT_EQ(to_string(InteractionState::NotReady), "NOT_READY");
  EXPECT_EQ(to_string(InteractionState::Complete), "COMPLETE");
}

TEST(Vocabulary, ServicesRoundTripAndHaveElementNames) {
  for (const auto s : kAllServices) {
    const auto parsed = parse_service(to_string(s));
    ASSERT_TRUE(parsed.has_value()) << to_string(s);
    EXPECT_EQ(*parsed, s);
    EXPECT_FALSE(element_name(s).empty());
  }
  EXPECT_EQ(to_string(Service::MaterialLoad), "MATERIAL_LOAD");
  EXPECT_EQ(element_name(Service::CloseChuck), "CloseChuck");
}

TEST(Vocabulary, InterfaceTypesRoundTripBothSpellings) {
  for (const auto t : kAllInterfaceTypes) {
    EXPECT_EQ(parse_interface_type(to_string(t)), t);
    EXPECT_EQ(parse_interface_type(element_name(t)), t);
  }
  EXPECT_EQ(state_item_type(InterfaceType::Door), "DOOR_STATE");
  EXPECT_EQ(state_item_type(InterfaceType::Chuck), "CHUCK_STATE");
  EXPECT_TRUE(state_item_type(InterfaceType::BarFeeder).empty());
}

TEST(Vocabulary, OtherValueSetsRoundTrip) {
  for (const auto s :
       {InterfaceState::Unavailable, InterfaceState::Enabled, InterfaceState::Disabled}) {
    EXPECT_EQ(parse_interface_state(to_string(s)), s);
  }
  for (const auto s :
       {DoorState::Unavailable, DoorState::Open, DoorState::Unlatched, DoorState::Closed}) {
    EXPECT_EQ(parse_door_state(to_string(s)), s);
  }
  for (const auto s :
       {ChuckState::Unavailable, ChuckState::Open, ChuckState::Unlatched, ChuckState::Closed}) {
    EXPECT_EQ(parse_chuck_state(to_string(s)), s);
  }
  for (const auto s : {SubType::Request, SubType::Response}) {
    EXPECT_EQ(parse_sub_type(to_string(s)), s);
  }
}

TEST(Vocabulary, RejectsTextOutsideTheVocabulary) {
  for (const char* bad : {"", "ready", "NOT READY", "READY ", "DONE", "COMPLETED", "\xff"}) {
    EXPECT_FALSE(parse_interaction_state(bad).has_value()) << bad;
    EXPECT_FALSE(parse_service(bad).has_value()) << bad;
  }
  EXPECT_FALSE(parse_interface_state("ACTIVE").has_value());
}

TEST(Vocabulary, OutOfRangeEnumsNeverCrash) {
  const auto garbage = static_cast<InteractionState>(200);
  EXPECT_FALSE(to_string(garbage).empty());
  EXPECT_EQ(seen_event(garbage), Event::SeenInvalid);
  EXPECT_EQ(to_string(static_cast<Reason>(250)), "?");
}

TEST(Vocabulary, RequestNeverTakesComplete) {
  EXPECT_FALSE(is_valid_request_state(InteractionState::Complete));
  EXPECT_TRUE(is_valid_request_state(InteractionState::Active));
}

TEST(Vocabulary, EveryMachineNameHasASpelling) {
  for (std::size_t i = 0; i < kEventCount; ++i) {
    EXPECT_NE(to_string(static_cast<Event>(i)), "?") << i;
  }
  for (int i = 0; i <= static_cast<int>(Notice::CommsRestored); ++i) {
    EXPECT_NE(to_string(static_cast<Notice>(i)), "?") << i;
  }
  for (int i = 0; i <= static_cast<int>(Reason::InvalidTarget); ++i) {
    EXPECT_NE(to_string(static_cast<Reason>(i)), "?") << i;
    if (i > 0) {
      EXPECT_FALSE(describe(static_cast<Reason>(i)).empty()) << i;
    }
  }
}

}  // namespace
}  // namespace mtc::core
