// DomainObserver sees values, heartbeats and announcements of raw writers
// that follow the topic design, reports items and devices lost when their
// heartbeats stop or their writer is deleted, and hands the last known
// values over again when the heartbeats resume, once nothing announced is
// missing.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "mtc/dds/detail/entities.hpp"
#include "mtc/dds/detail/heartbeat_writer.hpp"
#include "mtc/dds/detail/topics.hpp"
#include "mtc/dds/domain_observer.hpp"
#include "mtc/idl/mtconnect_interfacesPubSubTypes.h"
#include "mtc/idl/type_support.hpp"
#include "mtc/qos/fastdds_qos.hpp"
#include "mtc/qos/participant_qos.hpp"
#include "mtc/qos/presets.hpp"
#include "transport.hpp"

namespace {

using namespace std::chrono_literals;
namespace topics = mtc::dds::detail::topics;

struct Recorder {
  std::mutex mutex;
  std::condition_variable cv;
  std::vector<mtc::dds::ObservedValue> values;
  std::vector<mtc::dds::ObservedDevice> devices;
  std::vector<std::pair<std::string, std::vector<std::string>>> lost;
  std::vector<std::string> devices_lost;
  int heartbeats = 0;

  mtc::dds::DomainObserverCallbacks callbacks() {
    mtc::dds::DomainObserverCallbacks cb;
    cb.on_value = [this](const mtc::dds::ObservedValue& v) { add([&] { values.push_back(v); }); };
    cb.on_device = [this](const mtc::dds::ObservedDevice& d) {
      add([&] { devices.push_back(d); });
    };
    cb.on_items_lost = [this](const std::string& d, const std::vector<std::string>& items) {
      add([&] { lost.emplace_back(d, items); });
    };
    cb.on_device_lost = [this](const std::string& d) { add([&] { devices_lost.push_back(d); }); };
    cb.on_heartbeat = [this](const mtc::dds::ObservedHeartbeat&) { add([&] { ++heartbeats; }); };
    return cb;
  }
  template <typename Fn>
  void add(Fn fn) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      fn();
    }
    cv.notify_all();
  }
  template <typename Pred>
  bool wait(Pred pred, std::chrono::milliseconds timeout = 10s) {
    std::unique_lock<std::mutex> lock(mutex);
    return cv.wait_for(lock, timeout, [&] { return pred(); });
  }
};

struct QuietListener : eprosima::fastdds::dds::DataWriterListener {};

// A minimal hand-made "device": one InteractionSample writer, one
// DeviceDescription writer and its heartbeat (group 0) in the device's
// partition.
class RawDevice {
 public:
  RawDevice(int domain, const std::string& uuid, const mtc::qos::Timing& timing = {})
      : participant_(domain,
                     mtc::qos::participant_qos(mtc::test::loopback<mtc::qos::ParticipantConfig>())),
        publisher_(participant_, {topics::device_partition(uuid)}),
        heartbeat_(participant_, publisher_, uuid, 0, timing),
        uuid_(uuid) {
    participant_.register_type(mtc::idl::type_support<mtc::idl::InteractionSamplePubSubType>());
    participant_.register_type(mtc::idl::type_support<mtc::idl::DeviceDescriptionPubSubType>());
    response_topic_ = std::make_unique<mtc::dds::detail::Topic>(
        participant_,
        topics::interaction_topic(mtc::core::SubType::Response, mtc::core::Service::MaterialLoad),
        "mtc::idl::InteractionSample", mtc::qos::fastdds_topic_qos(mtc::qos::state_topic()));
    description_topic_ = std::make_unique<mtc::dds::detail::Topic>(
        participant_, topics::kDeviceDescription, "mtc::idl::DeviceDescription",
        mtc::qos::fastdds_topic_qos(mtc::qos::device_description_topic()));
    writer_ = std::make_unique<mtc::dds::detail::Writer<mtc::idl::InteractionSample>>(
        publisher_, *response_topic_, mtc::qos::fastdds_writer_qos(mtc::qos::state_topic()),
        listener_);
    describer_ = std::make_unique<mtc::dds::detail::Writer<mtc::idl::DeviceDescription>>(
        publisher_, *description_topic_,
        mtc::qos::fastdds_writer_qos(mtc::qos::device_description_topic()), listener_);
  }
  void announce() {
    mtc::idl::DeviceDescription d;
    d.device_uuid(uuid_);
    d.name("raw device");
    mtc::idl::InterfaceDescription i;
    i.id("mh1");
    i.interface_type(mtc::idl::interface_types::MATERIAL_HANDLER);
    mtc::idl::DataItemDescription item;
    item.id("mh1_material_load_response");
    item.type("MATERIAL_LOAD");
    item.sub_type("RESPONSE");
    item.category("EVENT");
    i.data_items().push_back(item);
    d.interfaces().push_back(i);
    describer_->write(d);
  }
  void publish(mtc::idl::interaction_state::Value state, std::uint64_t seq) {
    mtc::idl::InteractionSample s;
    s.device_uuid(uuid_);
    s.data_item_id("mh1_material_load_response");
    s.interface_id("mh1");
    s.service(mtc::idl::services::MATERIAL_LOAD);
    s.sub_type(mtc::idl::sub_types::RESPONSE);
    s.state(state);
    s.sequence_number(seq);
    s.source_time_ns(topics::realtime_ns());
    writer_->write(s);
  }
  void drop_writer() { writer_.reset(); }
  // Disposes the response instance (as a writer does when it goes away).
  void dispose_value() {
    mtc::idl::InteractionSample s;
    s.device_uuid(uuid_);
    s.data_item_id("mh1_material_load_response");
    writer_->dispose(s);
  }
  // Every matched reader has acknowledged every value and disposal: Fast DDS
  // calls a reader's listener before its acknowledgment goes out, so the
  // observer has queued it before anything written after this returns.
  bool acknowledged(std::chrono::seconds bound) {
    return writer_->get().wait_for_acknowledgments(
               eprosima::fastrtps::Duration_t(static_cast<std::int32_t>(bound.count()), 0)) ==
           eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK;
  }
  // Its last heartbeat (period 0), with no disposal after it.
  void leave() { heartbeat_.leave(); }
  // One heartbeat announcing `changes` as the newest response change.
  void beat(std::uint64_t changes) {
    heartbeat_.announce_interaction(mtc::core::Service::MaterialLoad, mtc::core::SubType::Response,
                                    changes);
    heartbeat_.beat();
  }

 private:
  mtc::dds::detail::Participant participant_;
  mtc::dds::detail::Publisher publisher_;
  mtc::dds::detail::HeartbeatWriter heartbeat_;
  std::string uuid_;
  QuietListener listener_;
  std::unique_ptr<mtc::dds::detail::Topic> response_topic_;
  std::unique_ptr<mtc::dds::detail::Topic> description_topic_;
  std::unique_ptr<mtc::dds::detail::Writer<mtc::idl::InteractionSample>> writer_;
  std::unique_ptr<mtc::dds::detail::Writer<mtc::idl::DeviceDescription>> describer_;
};

mtc::dds::DomainObserverOptions options(int domain) {
  auto o = mtc::test::loopback<mtc::dds::DomainObserverOptions>();
  o.domain_id = domain;
  return o;
}

TEST(DomainObserver, SeesAnnouncementsValuesAndLossByLiveliness) {
  Recorder rec;
  mtc::dds::DomainObserver observer(options(20), rec.callbacks());
  RawDevice dev(20, "robot-1");
  dev.announce();
  dev.publish(mtc::idl::interaction_state::READY, 1);
  dev.beat(1);
  ASSERT_TRUE(
      rec.wait([&] { return !rec.devices.empty() && !rec.values.empty() && rec.heartbeats == 1; }));
  {
    std::lock_guard<std::mutex> lock(rec.mutex);
    EXPECT_EQ(rec.devices[0].device_uuid, "robot-1");
    ASSERT_EQ(rec.devices[0].interfaces.size(), 1u);
    EXPECT_EQ(rec.devices[0].interfaces[0].type, mtc::core::InterfaceType::MaterialHandler);
    EXPECT_EQ(rec.devices[0].interfaces[0].data_items.at(0).sub_type, "RESPONSE");
    const auto& v = rec.values[0];
    EXPECT_EQ(v.state, mtc::core::ObservedState(mtc::core::InteractionState::Ready));
    EXPECT_EQ(v.kind(), mtc::dds::ItemKind::Interaction);
    EXPECT_EQ(v.service, mtc::core::Service::MaterialLoad);
    EXPECT_EQ(v.sub_type, mtc::core::SubType::Response);
    EXPECT_EQ(v.sequence_number, 1u);
  }
  EXPECT_EQ(observer.devices().size(), 1u);
  // No heartbeat follows: the heartbeat's MANUAL_BY_TOPIC lease (300 ms)
  // expires; group 0 vouches for the item and for the device itself.
  const auto start = std::chrono::steady_clock::now();
  ASSERT_TRUE(rec.wait([&] { return !rec.lost.empty() && !rec.devices_lost.empty(); }));
  EXPECT_LT(std::chrono::steady_clock::now() - start, 3s);
  std::lock_guard<std::mutex> lock(rec.mutex);
  EXPECT_EQ(rec.lost[0].first, "robot-1");
  EXPECT_EQ(rec.lost[0].second, std::vector<std::string>{"mh1_material_load_response"});
  EXPECT_EQ(rec.devices_lost[0], "robot-1");
}

// The device's heartbeat every 100 ms from a thread of its own, announcing
// `changes`, while running (a timer, not a synchronisation sleep).
class Beater {
 public:
  explicit Beater(RawDevice& dev) : dev_(dev), thread_([this] { run(); }) {}
  Beater(const Beater&) = delete;
  Beater& operator=(const Beater&) = delete;
  ~Beater() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }
  void beat(std::uint64_t changes) {
    std::lock_guard<std::mutex> lock(mutex_);
    changes_ = changes;
    beating_ = true;
  }
  void pause() {
    std::lock_guard<std::mutex> lock(mutex_);
    beating_ = false;
  }

 private:
  void run() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!cv_.wait_for(lock, 100ms, [this] { return stop_; })) {
      if (beating_) dev_.beat(changes_);
    }
  }
  RawDevice& dev_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool stop_ = false;
  bool beating_ = false;
  std::uint64_t changes_ = 0;
  std::thread thread_;
};

// A heartbeat repeats nothing: when heartbeats resume after a loss the
// observer hands the last value over again, but only once every change the
// heartbeat announces has arrived (until then the value may be stale).
TEST(DomainObserver, RedeliversLastValuesOnceHeartbeatsResumeInStep) {
  Recorder rec;
  mtc::dds::DomainObserver observer(options(25), rec.callbacks());
  RawDevice dev(25, "robot-2");
  Beater beater(dev);
  dev.announce();
  dev.publish(mtc::idl::interaction_state::READY, 1);
  beater.beat(1);
  ASSERT_TRUE(rec.wait(
      [&] { return rec.values.size() == 1 && !rec.devices.empty() && rec.heartbeats > 0; }));
  beater.pause();
  ASSERT_TRUE(rec.wait([&] { return rec.lost.size() == 1 && rec.devices_lost.size() == 1; }))
      << "lost " << rec.lost.size() << ", devices lost " << rec.devices_lost.size();

  // Back, announcing change 2 that has not arrived: nothing is handed over
  // while a few heartbeats pass.
  int heartbeats = 0;
  {
    std::lock_guard<std::mutex> lock(rec.mutex);
    heartbeats = rec.heartbeats;
  }
  beater.beat(2);
  ASSERT_TRUE(rec.wait([&] { return rec.heartbeats >= heartbeats + 5; }));
  std::size_t announced = 0;
  {
    std::lock_guard<std::mutex> lock(rec.mutex);
    EXPECT_EQ(rec.values.size(), 1u);
    announced = rec.devices.size();
  }
  // Change 2 arrives as a change, not as a redelivery; the device is back.
  dev.publish(mtc::idl::interaction_state::NOT_READY, 2);
  ASSERT_TRUE(rec.wait([&] { return rec.values.size() == 2; }));
  ASSERT_TRUE(rec.wait([&] { return rec.devices.size() == announced + 1; }));
  {
    std::lock_guard<std::mutex> lock(rec.mutex);
    EXPECT_FALSE(rec.values[1].redelivered);
    EXPECT_EQ(rec.values[1].sequence_number, 2u);
  }

  // Lost again; back in step: the last value (NOT_READY) again, and the
  // device, whose announcement is repeated for the consumers.
  beater.pause();
  ASSERT_TRUE(rec.wait([&] { return rec.lost.size() == 2 && rec.devices_lost.size() == 2; }));
  beater.beat(2);
  ASSERT_TRUE(rec.wait([&] { return rec.values.size() == 3; }));
  std::lock_guard<std::mutex> lock(rec.mutex);
  EXPECT_TRUE(rec.values[2].redelivered);
  EXPECT_EQ(rec.values[2].state.interaction(), mtc::core::InteractionState::NotReady);
  EXPECT_EQ(rec.values[2].sequence_number, 2u);
  EXPECT_EQ(rec.devices.size(), announced + 2);
}

TEST(DomainObserver, ReportsLossWhenWriterIsDeleted) {
  Recorder rec;
  mtc::dds::DomainObserver observer(options(21), rec.callbacks());
  RawDevice dev(21, "cnc-1");
  dev.publish(mtc::idl::interaction_state::ACTIVE, 7);
  ASSERT_TRUE(rec.wait([&] { return !rec.values.empty(); }));
  dev.drop_writer();  // disposes its instances
  ASSERT_TRUE(rec.wait([&] { return !rec.lost.empty(); }));
  EXPECT_EQ(rec.lost[0].first, "cnc-1");
}

// An 8 s lease: a loss could be told only after it, so within the waits
// below only a leave can end a device.
mtc::qos::Timing slow_timing() {
  mtc::qos::Timing slow;
  slow.heartbeat = 1s;
  slow.missed_heartbeats = 8;
  return slow;
}

// The device announced, a READY value and a heartbeat written, and all three
// seen by the observer.
bool announced_and_heard(RawDevice& dev, Recorder& rec) {
  dev.announce();
  dev.publish(mtc::idl::interaction_state::READY, 1);
  dev.beat(1);
  return rec.wait(
      [&] { return !rec.devices.empty() && !rec.values.empty() && rec.heartbeats > 0; });
}

// The leave said in data, its disposals lost (a Cyclone reader of a Fast
// DDS device never gets them): told at once as the device gone, its items
// lost. With an 8 s lease, a loss would be told only after it: the wait
// below ends at half of it.
TEST(DomainObserver, TakesALeavingHeartbeatAsTheLeave) {
  const auto slow = slow_timing();
  Recorder rec;
  auto o = options(150);
  o.timing = slow;
  mtc::dds::DomainObserver observer(o, rec.callbacks());
  RawDevice dev(150, "cnc-leaving", slow);
  ASSERT_TRUE(announced_and_heard(dev, rec));
  dev.leave();
  ASSERT_TRUE(rec.wait([&] { return !rec.devices_lost.empty(); }, slow.lease() / 2));
  std::lock_guard<std::mutex> lock(rec.mutex);
  EXPECT_EQ(rec.devices_lost, std::vector<std::string>{"cnc-leaving"});
  ASSERT_EQ(rec.lost.size(), 1u);
  EXPECT_EQ(rec.lost[0].second, std::vector<std::string>{"mh1_material_load_response"});
}

// Call under rec.mutex (inside a wait's predicate) or with it held.
bool saw_state(const Recorder& rec, mtc::core::InteractionState state) {
  return std::any_of(rec.values.begin(), rec.values.end(),
                     [&](const auto& v) { return v.state.interaction() == state; });
}

// What an incarnation writes after its leave (a value that crossed the leave
// on another topic, or came from a writer that lingers after its
// participant, as Cyclone's do) is not news: the bridge would show a value
// of a device that is gone, and take it back once the disposals came.
TEST(DomainObserver, WhatALeftIncarnationWritesLaterIsNotNews) {
  constexpr int kDomain = 154;
  const auto slow = slow_timing();
  Recorder rec;
  auto o = options(kDomain);
  o.timing = slow;
  mtc::dds::DomainObserver observer(o, rec.callbacks());
  RawDevice dev(kDomain, "cnc-left", slow);
  ASSERT_TRUE(announced_and_heard(dev, rec));
  dev.leave();
  ASSERT_TRUE(rec.wait([&] { return !rec.devices_lost.empty(); }));
  dev.publish(mtc::idl::interaction_state::ACTIVE, 2);
  ASSERT_TRUE(dev.acknowledged(10s));

  RawDevice again(kDomain, "cnc-left", slow);
  again.announce();
  again.publish(mtc::idl::interaction_state::NOT_READY, 1);
  again.beat(1);
  ASSERT_TRUE(rec.wait([&] { return saw_state(rec, mtc::core::InteractionState::NotReady); }));
  std::lock_guard<std::mutex> lock(rec.mutex);
  EXPECT_FALSE(saw_state(rec, mtc::core::InteractionState::Active));
  EXPECT_EQ(rec.devices_lost, std::vector<std::string>{"cnc-left"});
  EXPECT_EQ(rec.lost.size(), 1u);
}

// A disposal by an earlier incarnation that arrives after its successor
// wrote the same instance ends nothing: the item is the successor's.
TEST(DomainObserver, AnEarlierIncarnationsDisposalLeavesItsSuccessorsItemAlone) {
  constexpr int kDomain = 155;
  Recorder rec;
  mtc::dds::DomainObserver observer(options(kDomain), rec.callbacks());
  RawDevice old_one(kDomain, "cnc-twice");
  old_one.publish(mtc::idl::interaction_state::READY, 1);
  ASSERT_TRUE(rec.wait([&] { return saw_state(rec, mtc::core::InteractionState::Ready); }));
  RawDevice new_one(kDomain, "cnc-twice");
  new_one.publish(mtc::idl::interaction_state::ACTIVE, 1);
  ASSERT_TRUE(rec.wait([&] { return saw_state(rec, mtc::core::InteractionState::Active); }));
  old_one.dispose_value();
  ASSERT_TRUE(old_one.acknowledged(10s));
  new_one.publish(mtc::idl::interaction_state::COMPLETE, 2);
  ASSERT_TRUE(rec.wait([&] { return saw_state(rec, mtc::core::InteractionState::Complete); }));
  std::lock_guard<std::mutex> lock(rec.mutex);
  EXPECT_TRUE(rec.lost.empty()) << rec.lost.size() << " loss(es) told";
}

TEST(DomainObserver, DeviceFilterHidesOtherDevices) {
  Recorder rec;
  auto o = options(22);
  o.device_filter = {"wanted"};
  mtc::dds::DomainObserver observer(o, rec.callbacks());
  RawDevice other(22, "other");
  RawDevice wanted(22, "wanted");
  other.publish(mtc::idl::interaction_state::READY, 1);
  wanted.publish(mtc::idl::interaction_state::FAIL, 2);
  ASSERT_TRUE(rec.wait([&] { return !rec.values.empty(); }));
  std::lock_guard<std::mutex> lock(rec.mutex);
  for (const auto& v : rec.values) EXPECT_EQ(v.device_uuid, "wanted");
  EXPECT_EQ(rec.values[0].state.interaction(), mtc::core::InteractionState::Fail);
}

// A peer of another implementation may send a number the IDL enum does not
// name: the observer hands it over as such, never as a known state. Over
// Cyclone DDS it never arrives: Cyclone 0.10's deserializer refuses an enum
// value its type does not name (its log: "deserialization ... failed"), so
// the sample is dropped before the runtime sees it, and what the same writer
// sends next arrives as usual.
TEST(DomainObserver, StateOutsideTheVocabularyIsKeptAsSent) {
  Recorder rec;
  mtc::dds::DomainObserver observer(options(24), rec.callbacks());
  RawDevice dev(24, "robot-1");
  dev.publish(static_cast<mtc::idl::interaction_state::Value>(9), 1);
  if (mtc::test::test_middleware_is_cyclone()) {
    dev.publish(mtc::idl::interaction_state::READY, 2);
    ASSERT_TRUE(rec.wait([&] { return !rec.values.empty(); }));
    std::lock_guard<std::mutex> lock(rec.mutex);
    ASSERT_EQ(rec.values.size(), 1u);
    EXPECT_EQ(rec.values[0].state.interaction(), mtc::core::InteractionState::Ready);
    return;
  }
  ASSERT_TRUE(rec.wait([&] { return !rec.values.empty(); }));
  std::lock_guard<std::mutex> lock(rec.mutex);
  const auto& state = rec.values[0].state;
  EXPECT_EQ(state.kind(), mtc::dds::ItemKind::Interaction);
  EXPECT_FALSE(state.in_vocabulary());
  EXPECT_EQ(state.raw(), 9);
  EXPECT_FALSE(state.interaction().has_value());
}

TEST(DomainObserver, BadOptionsThrowTypedErrors) {
  Recorder rec;
  auto o = options(23);
  o.timing.missed_heartbeats = 1;
  EXPECT_THROW(mtc::dds::DomainObserver(o, rec.callbacks()), mtc::dds::ConfigError);
  o = options(500);
  EXPECT_THROW(mtc::dds::DomainObserver(o, rec.callbacks()), mtc::dds::Error);
}

}  // namespace
