// Each data item an Equipment publishes is one DDS instance, for the whole
// run. Before mtc::idl::type_support, one key reached readers under several
// instance handles (stale padding hashed into the key), and every stray
// instance kept an old sample in the writer's history for good.
#include <fastrtps/xmlparser/XMLProfileManager.h>
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "equipment_fixture.hpp"
#include "mtc/dds/detail/entities.hpp"
#include "mtc/dds/detail/topics.hpp"
#include "mtc/idl/mtconnect_interfacesPubSubTypes.h"
#include "mtc/idl/type_support.hpp"
#include "mtc/qos/fastdds_qos.hpp"
#include "mtc/qos/participant_qos.hpp"
#include "mtc/qos/presets.hpp"
#include "transport.hpp"

namespace mtc::dds::testing {

// Raw peers build their entities from the runtime's internals.
namespace fdds = detail::fdds;
namespace topics = detail::topics;
using detail::Participant;
using detail::Reader;
using detail::Subscriber;
using detail::Topic;
namespace {

using core::InterfaceType;
using eprosima::fastrtps::rtps::InstanceHandle_t;

constexpr int kDomain = 57;

// Every instance handle under which each (device, data item) arrives.
class HandleCounter : public fdds::DataReaderListener {
 public:
  void on_data_available(fdds::DataReader* reader) override {
    idl::InteractionSample s;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&s, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      std::lock_guard<std::mutex> lock(mutex_);
      auto& seen = items_[s.device_uuid().to_string() + "/" + s.data_item_id().to_string()];
      seen.handles.insert(info.instance_handle);
      ++seen.samples;
      cv_.notify_all();
    }
  }
  // Whether `count` items have each arrived `samples` times.
  bool seen(std::size_t count, int samples) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::size_t ready = 0;
    for (const auto& [key, item] : items_) ready += item.samples >= samples ? 1 : 0;
    return ready >= count;
  }
  // Until `count` items have each arrived `samples` times.
  bool wait_for(std::size_t count, int samples) {
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, kTimeout, [&] {
      std::size_t ready = 0;
      for (const auto& [key, seen] : items_) ready += seen.samples >= samples ? 1 : 0;
      return ready >= count;
    });
  }
  struct Seen {
    std::set<InstanceHandle_t> handles;
    int samples = 0;
  };
  std::string summary() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::string out;
    for (const auto& [key, seen] : items_) out += key + ": " + std::to_string(seen.samples) + "\n";
    return out;
  }
  std::map<std::string, Seen> items() {
    std::lock_guard<std::mutex> lock(mutex_);
    return items_;
  }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  std::map<std::string, Seen> items_;
};

InstanceHandle_t spec_handle(const std::string& key) {
  const auto slash = key.find('/');
  idl::InteractionSample s;
  s.device_uuid(key.substr(0, slash));
  s.data_item_id(key.substr(slash + 1));
  InstanceHandle_t h;
  idl::compute_key_hash(s, h, false);
  return h;
}

// As between processes: with intra-process delivery a reader gets the
// writer's handle along with the sample and never hashes a key itself, and
// it is hashing other devices' keys that left stale bytes for our own.
void deliver_through_transports() {
  eprosima::fastrtps::LibrarySettingsAttributes settings;
  settings.intraprocess_delivery = eprosima::fastrtps::INTRAPROCESS_OFF;
  eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings(settings);
}

TEST(InstanceKeys, EveryDataItemIsOneInstanceWhileHandshakesRun) {
  deliver_through_transports();
  // Device uuids and interface ids of different lengths: the stale bytes a
  // key hash used to pick up differed with the key hashed before it.
  Equipment cnc(options(kDomain, "c"));
  Equipment robot(options(kDomain, "robot-with-a-longer-uuid"));
  cnc.add_interface({"mh", InterfaceType::MaterialHandler, "", {"robot-with-a-longer-uuid", "mh"}});
  cnc.add_interface(
      {"door_one", InterfaceType::Door, "", {"robot-with-a-longer-uuid", "door_one"}});
  robot.add_interface({"mh", InterfaceType::MaterialHandler, "", {"c", "mh"}});
  robot.add_interface({"door_one", InterfaceType::Door, "", {"c", "door_one"}});
  auto& load = cnc.add_requester("mh", Service::MaterialLoad);
  auto& unload = cnc.add_requester("mh", Service::MaterialUnload);
  auto& open = robot.add_requester("door_one", Service::OpenDoor);
  ResponderCallbacks complete_at_once;
  complete_at_once.on_request = [](Responder& r) { r.complete(); };
  robot.add_responder("mh", Service::MaterialLoad, complete_at_once);
  robot.add_responder("mh", Service::MaterialUnload, complete_at_once);
  cnc.add_responder("door_one", Service::OpenDoor, complete_at_once);

  Participant participant(kDomain,
                          qos::participant_qos(mtc::test::loopback<qos::ParticipantConfig>()));
  participant.register_type(idl::type_support<idl::InteractionSamplePubSubType>());
  // Both sides of the three services: one topic each.
  std::vector<std::unique_ptr<Topic>> interaction_topics;
  for (auto service : {Service::MaterialLoad, Service::MaterialUnload, Service::OpenDoor}) {
    for (auto side : {core::SubType::Request, core::SubType::Response}) {
      interaction_topics.push_back(std::make_unique<Topic>(
          participant, topics::interaction_topic(side, service), "mtc::idl::InteractionSample",
          qos::fastdds_topic_qos(qos::state_topic())));
    }
  }
  Subscriber subscriber(participant, {topics::kAllDevicesPartition});
  HandleCounter counter;
  std::vector<std::unique_ptr<Reader>> readers;
  readers.reserve(interaction_topics.size());
  for (auto& topic : interaction_topics) {
    readers.push_back(std::make_unique<Reader>(
        subscriber, *topic, qos::fastdds_reader_qos(qos::state_topic()), &counter));
  }

  cnc.start();
  robot.start();
  // start() publishes each of the six interaction items (TRANSIENT_LOCAL),
  // and a writer sends to a reader only once it has matched it: when all six
  // have arrived, each of the six writers (one per item: a service and a
  // side) has matched the test's readers.
  // The handshakes take a few hundred ms; begun earlier, they could all be
  // over before a late-discovered writer matched, leaving the readers with
  // its items' last values only, and nothing written after them.
  ASSERT_TRUE(counter.wait_for(6, 1)) << counter.summary();
  // Items are written on change only: handshakes until the test's readers
  // have seen each of the six interaction items change a few times.
  RequestOptions wait;
  wait.wait_for_ready = kTimeout;
  for (int i = 0; i < 50 && !counter.seen(6, 6); ++i) {
    ASSERT_EQ(load.request(wait).get().outcome, Outcome::Completed);
    ASSERT_EQ(unload.request(wait).get().outcome, Outcome::Completed);
    ASSERT_EQ(open.request(wait).get().outcome, Outcome::Completed);
  }
  ASSERT_TRUE(counter.wait_for(6, 6)) << counter.summary();
  for (const auto& [key, seen] : counter.items()) {
    ASSERT_EQ(seen.handles.size(), 1u)
        << key << " arrived under " << seen.handles.size() << " instance handles";
    EXPECT_EQ(*seen.handles.begin(), spec_handle(key)) << key;
  }
}

}  // namespace
}  // namespace mtc::dds::testing
