// No false comms-loss alarms: a DEADLINE miss is not a lost link while the
// counterpart interface keeps heartbeating. Fast DDS 2.9 reports whichever
// instance owns a reader's single deadline timer and re-fires every period
// for an instance that stopped receiving samples; between processes,
// instance handles of one key also varied (stale padding hashed into the key,
// docs/endurance.md), leaving stale instances behind. Either way a silent
// instance of the counterpart device used to fail a healthy link every lease.
#include <gtest/gtest.h>

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "equipment_fixture.hpp"
#include "mtc/dds/detail/entities.hpp"
#include "mtc/dds/detail/topics.hpp"
#include "mtc/idl/mtconnect_interfacesPubSubTypes.h"
#include "mtc/idl/type_support.hpp"
#include "mtc/qos/participant_qos.hpp"
#include "mtc/qos/presets.hpp"

namespace mtc::dds::testing {

// Raw peers build their entities from the runtime's internals.
using namespace mtc::dds::detail;
namespace {

using core::InterfaceType;

// A second writer of the counterpart device (say a retired tool of it) that
// published one item once and now only asserts its liveliness: the writer
// is alive, that instance is silent for good.
class SilentItemWriter {
 public:
  SilentItemWriter(int domain, const std::string& uuid, const std::string& interface_id)
      : participant_(domain, qos::participant_qos({})),
        publisher_(participant_, {topics::device_partition(uuid)}) {
    participant_.register_type(idl::type_support<idl::InteractionSamplePubSubType>());
    topic_ = std::make_unique<Topic>(participant_, topics::kInteractionResponse,
                                     "mtc::idl::InteractionSample", qos::state_topic().topic_qos());
    writer_ = std::make_unique<Writer<idl::InteractionSample>>(
        publisher_, *topic_, qos::state_topic().writer_qos(), listener_);
    idl::InteractionSample s;
    s.device_uuid(uuid);
    s.interface_id(interface_id);
    s.data_item_id(item_id(interface_id));
    s.service(topics::to_idl(core::Service::MaterialUnload));
    s.sub_type(topics::to_idl(core::SubType::Response));
    s.state(topics::to_idl(core::InteractionState::NotReady));
    s.sequence_number(1);
    s.source_time_ns(topics::realtime_ns());
    writer_->write(s);
    thread_ = std::thread([this] { keep_alive(); });
  }
  ~SilentItemWriter() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }
  static std::string item_id(const std::string& interface_id) {
    return interface_id + "_retired_item";
  }

 private:
  // MANUAL_BY_TOPIC liveliness without samples (a timer, not a
  // synchronisation sleep).
  void keep_alive() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!cv_.wait_for(lock, std::chrono::milliseconds(50), [this] { return stop_; })) {
      writer_->assert_liveliness();
    }
  }

  struct QuietListener : fdds::DataWriterListener {};
  Participant participant_;
  Publisher publisher_;
  QuietListener listener_;
  std::unique_ptr<Topic> topic_;
  std::unique_ptr<Writer<idl::InteractionSample>> writer_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool stop_ = false;
  std::thread thread_;
};

TEST(FalseAlarms, SilentInstanceOfALiveCounterpartDoesNotLoseTheLink) {
  Recorder rec;
  std::atomic<bool> saw_silent_item{false};
  auto cb = rec.callbacks();
  cb.on_counterpart_value = [&](const ObservedValue& v) {
    if (v.data_item_id == SilentItemWriter::item_id("mh1")) saw_silent_item = true;
    rec.notify();
  };
  Equipment cnc(options(56, "cnc-fa"), cb);
  Equipment robot(options(56, "robot-fa"));
  cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"robot-fa", "mh1"}});
  robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"cnc-fa", "mh1"}});
  SilentItemWriter retired(56, "robot-fa", "mh1");
  cnc.start();
  robot.start();
  ASSERT_TRUE(rec.wait_link(cnc, "mh1", LinkState::Up)) << rec.dump();
  ASSERT_TRUE(rec.wait([&] { return saw_silent_item.load(); })) << rec.dump();

  // Five leases (default timing: 100 ms x 3) during which the silent
  // instance misses its deadline again and again while robot-fa heartbeats.
  EXPECT_FALSE(rec.wait_link(cnc, "mh1", LinkState::Lost, std::chrono::milliseconds(1500)))
      << rec.dump();
  // A loss healed by the next heartbeat would not show in the state: check
  // every link event too.
  for (const auto& l : rec.links()) {
    EXPECT_NE(l.current, LinkState::Lost) << l.cause << "\n" << rec.dump();
  }
  EXPECT_EQ(cnc.link_state("mh1"), LinkState::Up);
}

}  // namespace
}  // namespace mtc::dds::testing
