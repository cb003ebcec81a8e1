// The middleware seam (dds/src/mw/middleware.hpp) over both backends and
// across them: a writer's participant on Fast DDS or Cyclone DDS, a tap's on
// either, in one process and one domain, on loopback UDP. Each case checks
// what the runtime relies on: values, heartbeats and announcements arrive
// field by field, a writer is named by its GUID (whose prefix is the
// writing participant's key, on either vendor), a disposal names the
// instance its value arrived on, a deleted writer is reported unmatched,
// and a value on another service's topic is refused.
//
// Domain 141 (registry: tests/dds/CMakeLists.txt); each case has its own
// partition, and the cases hold one resource lock, so that they never share
// the domain with another process's.
#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "mtc/dds/error.hpp"
#include "mtc/qos/cyclone_qos.hpp"
#include "mtc/qos/presets.hpp"
#include "mw/cyclone_backend.hpp"
#include "mw/cyclone_entities.hpp"
#include "mw/middleware.hpp"
#include "wire_values.hpp"

namespace mtc::dds {
namespace {

using namespace std::chrono_literals;
using detail::TapEvent;
using detail::TopicKind;

constexpr int kDomain = 141;
constexpr auto kArrival = 20s;  // discovery and delivery on a loaded 2-core machine

enum class Backend { FastDds, Cyclone };

std::unique_ptr<mw::Participant> make_participant(Backend b) {
  qos::ParticipantConfig config;
  config.transport = qos::Transport::LoopbackUdp;
  return b == Backend::FastDds ? mw::make_fastdds_participant(kDomain, config)
                               : mw::make_cyclone_participant(kDomain, config);
}

// Every event a tap hands on, kept for the test thread to wait on.
class Events {
 public:
  detail::TapSink sink() {
    return [this](TapEvent&& e) {
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        events_.push_back(std::move(e));
      }
      changed_.notify_all();
    };
  }
  // The first event of type T that `match` accepts, waiting for it.
  template <typename T>
  std::optional<T> wait_for(const std::function<bool(const T&)>& match = {},
                            std::chrono::milliseconds timeout = kArrival) {
    std::unique_lock<std::mutex> lock(mutex_);
    std::optional<T> found;
    changed_.wait_for(lock, timeout, [&] {
      for (const auto& e : events_) {
        if (const auto* t = std::get_if<T>(&e); t && (!match || match(*t))) {
          found = *t;
          return true;
        }
      }
      return false;
    });
    return found;
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<TapEvent> events_;
};

struct Pair {
  Backend writer;
  Backend reader;
};

std::string name_of(const testing::TestParamInfo<Pair>& info) {
  const auto n = [](Backend b) { return b == Backend::FastDds ? "FastDds" : "Cyclone"; };
  return std::string(n(info.param.writer)) + "To" + n(info.param.reader);
}

// A writer's participant and a reader's, with a tap on the reader's.
class Backends : public testing::TestWithParam<Pair> {
 protected:
  void SetUp() override {
    const auto* test = testing::UnitTest::GetInstance()->current_test_info();
    partitions_ = {std::string("mtc/test/") + test->name()};
    writer_side_ = make_participant(GetParam().writer);
    reader_side_ = make_participant(GetParam().reader);
    detail::TapConfig config;
    config.partitions = partitions_;
    tap_ = reader_side_->tap(config, events_.sink());
    publisher_ = writer_side_->publisher(partitions_);
  }
  void TearDown() override {
    tap_.reset();
    publisher_.reset();
  }

  std::vector<std::string> partitions_;
  Events events_;
  std::unique_ptr<mw::Participant> writer_side_;
  std::unique_ptr<mw::Participant> reader_side_;
  std::unique_ptr<mw::Tap> tap_;
  std::unique_ptr<mw::Publisher> publisher_;
};

TEST_P(Backends, AStateValueArrivesNamedByItsWritersGuid) {
  auto writer = publisher_->value_writer(TopicKind::InterfaceState, 0, qos::state_topic());
  const auto sent = wire_test::value(core::ItemKind::InterfaceState);
  writer->write(sent, {});
  const auto got = events_.wait_for<detail::ValueEvent>();
  ASSERT_TRUE(got);
  EXPECT_EQ(got->topic, TopicKind::InterfaceState);
  wire_test::expect_same(sent, got->value);
  EXPECT_EQ(detail::participant_of(got->writer), writer_side_->key());
  EXPECT_NE(writer_side_->key(), reader_side_->key());
  EXPECT_EQ(tap_->counts().values, 1U);
}

TEST_P(Backends, AnInteractionValueCarriesItsPairedParticipant) {
  const auto sent = wire_test::value(core::ItemKind::Interaction);
  const auto topic = detail::interaction_index(*sent.sub_type, *sent.service);
  auto writer = publisher_->value_writer(TopicKind::Response, topic, qos::state_topic());
  const auto paired = reader_side_->key();
  writer->write(sent, paired);
  const auto got = events_.wait_for<detail::ValueEvent>();
  ASSERT_TRUE(got);
  EXPECT_EQ(got->topic, TopicKind::Response);
  wire_test::expect_same(sent, got->value);
  EXPECT_EQ(got->paired, paired);
}

TEST_P(Backends, AValueOnAnotherServicesTopicIsRefused) {
  const auto sent = wire_test::value(core::ItemKind::Interaction);  // MATERIAL_LOAD response
  const auto other =
      detail::interaction_index(core::SubType::Response, core::Service::MaterialUnload);
  auto writer = publisher_->value_writer(TopicKind::Response, other, qos::state_topic());
  writer->write(sent, {});
  const auto got = events_.wait_for<detail::ProtocolViolationEvent>();
  ASSERT_TRUE(got);
  EXPECT_EQ(got->topic, other);
  EXPECT_EQ(detail::participant_of(got->writer), writer_side_->key());
  EXPECT_FALSE(events_.wait_for<detail::ValueEvent>({}, 0ms));
  EXPECT_EQ(tap_->counts().values, 0U);
}

TEST_P(Backends, AHeartbeatAndAnAnnouncementArrive) {
  auto beats = publisher_->heartbeat_writer(qos::heartbeat_topic());
  auto announcer = publisher_->device_writer(qos::device_description_topic());
  const auto device = wire_test::device();
  announcer->write(device, 42, 1'795'525'998'000'000'000);
  const auto announced = events_.wait_for<detail::DeviceEvent>();
  ASSERT_TRUE(announced);
  wire_test::expect_same(device, announced->device);
  EXPECT_EQ(detail::participant_of(announced->writer), writer_side_->key());

  // Heartbeats are volatile: one sent before the reader matched is not kept
  // for it, so beat as a device does until one arrives.
  const auto sent = wire_test::heartbeat();
  std::optional<detail::HeartbeatEvent> got;
  for (int beat = 0; beat < 200 && !got; ++beat) {
    beats->write(sent);
    got = events_.wait_for<detail::HeartbeatEvent>({}, 100ms);
  }
  ASSERT_TRUE(got);
  wire_test::expect_same(sent, got->heartbeat);
  EXPECT_EQ(detail::participant_of(got->writer), writer_side_->key());
  EXPECT_GE(tap_->counts().heartbeats, 1U);
}

TEST_P(Backends, ADeletedWriterIsReportedUnmatched) {
  auto writer = publisher_->value_writer(TopicKind::DoorState, 0, qos::state_topic());
  writer->write(wire_test::value(core::ItemKind::DoorState), {});
  const auto value = events_.wait_for<detail::ValueEvent>();
  ASSERT_TRUE(value);
  writer.reset();
  const auto gone = events_.wait_for<detail::WriterLivelinessEvent>(
      [&](const detail::WriterLivelinessEvent& e) { return e.unmatched; });
  ASSERT_TRUE(gone);
  EXPECT_EQ(gone->topic, TopicKind::DoorState);
  EXPECT_FALSE(gone->alive);
  EXPECT_EQ(gone->writer, value->writer);
}

TEST_P(Backends, AcknowledgmentsAreWaitedFor) {
  auto writer = publisher_->value_writer(TopicKind::ChuckState, 0, qos::state_topic());
  writer->write(wire_test::value(core::ItemKind::ChuckState), {});
  ASSERT_TRUE(events_.wait_for<detail::ValueEvent>());
  EXPECT_TRUE(publisher_->wait_for_acknowledgments(kArrival));
}

// Fast DDS 2.9 sends a disposal as a key hash alone, which Cyclone cannot
// map to a key (docs/design/middleware-layer.md, "Disposal"), so that pair
// has a case of its own (the leave is said in data anyway).
class Disposals : public Backends {};
class DisposalsDropped : public Backends {};

TEST_P(Disposals, NameTheInstanceTheValueArrivedOn) {
  auto writer = publisher_->value_writer(TopicKind::InterfaceState, 0, qos::state_topic());
  const auto sent = wire_test::value(core::ItemKind::InterfaceState);
  writer->write(sent, {});
  const auto value = events_.wait_for<detail::ValueEvent>();
  ASSERT_TRUE(value);
  writer->dispose(sent.device_uuid, sent.data_item_id);
  const auto gone = events_.wait_for<detail::InstanceGoneEvent>();
  ASSERT_TRUE(gone);
  EXPECT_TRUE(gone->disposed);
  EXPECT_EQ(gone->topic, TopicKind::InterfaceState);
  EXPECT_EQ(gone->instance, value->instance);
}

// The disposal never arrives; the instance is gone for want of writers once
// its writer is deleted. Had the disposal arrived, it would come first.
TEST_P(DisposalsDropped, ReachTheReaderOnlyAsTheWritersLoss) {
  auto writer = publisher_->value_writer(TopicKind::InterfaceState, 0, qos::state_topic());
  const auto sent = wire_test::value(core::ItemKind::InterfaceState);
  writer->write(sent, {});
  const auto value = events_.wait_for<detail::ValueEvent>();
  ASSERT_TRUE(value);
  writer->dispose(sent.device_uuid, sent.data_item_id);
  ASSERT_TRUE(publisher_->wait_for_acknowledgments(kArrival));
  writer.reset();
  const auto gone = events_.wait_for<detail::InstanceGoneEvent>();
  ASSERT_TRUE(gone);
  EXPECT_FALSE(gone->disposed);
  EXPECT_EQ(gone->instance, value->instance);
}

INSTANTIATE_TEST_SUITE_P(Mw, Disposals,
                         testing::Values(Pair{Backend::FastDds, Backend::FastDds},
                                         Pair{Backend::Cyclone, Backend::Cyclone},
                                         Pair{Backend::Cyclone, Backend::FastDds}),
                         name_of);
INSTANTIATE_TEST_SUITE_P(Mw, DisposalsDropped,
                         testing::Values(Pair{Backend::FastDds, Backend::Cyclone}), name_of);
INSTANTIATE_TEST_SUITE_P(Mw, Backends,
                         testing::Values(Pair{Backend::FastDds, Backend::FastDds},
                                         Pair{Backend::Cyclone, Backend::Cyclone},
                                         Pair{Backend::FastDds, Backend::Cyclone},
                                         Pair{Backend::Cyclone, Backend::FastDds}),
                         name_of);

// What the Cyclone backend cannot honour is refused at once, saying so: Fast
// DDS's fault-injecting test transport, a security directory that is not
// there (the pre-flight check, before Cyclone sees it), a bad timing.
TEST(MwCyclone, RefusesWhatItCannotHonour) {
  qos::ParticipantConfig faulty;
  faulty.transport = qos::Transport::LoopbackTest;
  try {
    mw::make_cyclone_participant(kDomain, faulty);
    FAIL() << "a participant on the test transport was made";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("'test'"), std::string::npos) << e.what();
  }
  qos::ParticipantConfig secure;
  secure.transport = qos::Transport::LoopbackUdp;
  secure.security_dir = "/nonexistent";
  try {
    mw::make_cyclone_participant(kDomain, secure);
    FAIL() << "a participant with a missing security directory was made";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent"), std::string::npos) << e.what();
  }
  qos::ParticipantConfig bad_timing;
  bad_timing.transport = qos::Transport::LoopbackUdp;
  bad_timing.timing.missed_heartbeats = 1;
  EXPECT_THROW(mw::make_cyclone_participant(kDomain, bad_timing), ConfigError);
}

// One Cyclone domain per id and process: participants of one configuration
// share it, another configuration is refused while it lives, and the id is
// free again once its last participant is gone.
TEST(MwCyclone, ParticipantsOfOneDomainShareItsConfiguration) {
  qos::ParticipantConfig config;
  config.transport = qos::Transport::LoopbackUdp;
  auto first = mw::make_cyclone_participant(kDomain, config);
  auto second = mw::make_cyclone_participant(kDomain, config);
  EXPECT_NE(first->key(), second->key());
  qos::ParticipantConfig slower = config;
  slower.timing.reliable_heartbeat *= 2;
  EXPECT_THROW(mw::make_cyclone_participant(kDomain, slower), ConfigError);
  first.reset();
  second.reset();
  EXPECT_NO_THROW(mw::make_cyclone_participant(kDomain, slower));
}

// The network transport names the host's interfaces, read once per domain:
// a participant that joins a live domain asks for the same transport and
// timing and shares it, whatever the interfaces are by then; only another
// recipe is refused.
TEST(MwCyclone, ADomainReadsTheHostsInterfacesOnceWhileItLives) {
  int configs_made = 0;
  auto recipe = [&configs_made](const std::string& name, const std::vector<std::string>& ifs) {
    return mw::cyclone::DomainRecipe{name, [&configs_made, ifs] {
                                       ++configs_made;
                                       return qos::cyclone_network_config({}, ifs);
                                     }};
  };
  {
    const auto first = mw::cyclone::acquire_domain(kDomain, recipe("network", {"lo"}));
    const auto later = mw::cyclone::acquire_domain(kDomain, recipe("network", {"mtc-absent0"}));
    EXPECT_EQ(first, later);
    EXPECT_EQ(configs_made, 1);
    EXPECT_THROW(mw::cyclone::acquire_domain(kDomain, recipe("loopback", {})), ConfigError);
    EXPECT_EQ(configs_made, 1);
  }

  qos::ParticipantConfig network;
  network.transport = qos::Transport::Network;
  auto one = mw::make_cyclone_participant(kDomain, network);
  auto two = mw::make_cyclone_participant(kDomain, network);
  EXPECT_NE(one->key(), two->key());
  qos::ParticipantConfig slower = network;
  slower.timing.reliable_heartbeat *= 2;
  EXPECT_THROW(mw::make_cyclone_participant(kDomain, slower), ConfigError);
}

}  // namespace
}  // namespace mtc::dds
