#include "rogue_peer.hpp"

#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include "mtc/dds/detail/entities.hpp"
#include "mtc/dds/detail/heartbeat_writer.hpp"
#include "mtc/dds/detail/topics.hpp"
#include "mtc/dds/domain_observer.hpp"
#include "mtc/idl/mtconnect_interfacesPubSubTypes.h"
#include "mtc/idl/type_support.hpp"
#include "mtc/qos/fastdds_qos.hpp"
#include "mtc/qos/participant_qos.hpp"
#include "mtc/qos/presets.hpp"

namespace mtc::test {

namespace fdds = eprosima::fastdds::dds;

namespace {
// The same lease as the `mtc` processes of the tests (mtc_fixture.hpp):
// QoS only matches when both sides offer/request the same lease.
qos::Timing rogue_timing() {
  qos::Timing t;
  t.missed_heartbeats = 10;
  return t;
}
}  // namespace

struct RoguePeer::Impl {
  struct Listener : fdds::DataWriterListener {};

  Impl(int domain, const std::string& device, const qos::Timing& t)
      : timing(t),
        participant(domain, qos::participant_qos(
                                {"rogue-" + device, qos::Transport::LoopbackUdp, {}, t, ""})) {}

  // Writes the current value as a change.
  void publish() {
    std::lock_guard<std::mutex> lock(mutex);
    sample.sequence_number(sample.sequence_number() + 1);
    sample.source_time_ns(dds::detail::topics::realtime_ns());
    writer->write(sample);
  }

  // The heartbeat, announcing the newest change.
  void beat() {
    std::lock_guard<std::mutex> lock(mutex);
    // The topic's service and side: the sample may claim another service
    // (a test of the peer checks).
    heartbeat->announce_interaction(topic_service, topic_side, sample.sequence_number());
    heartbeat->beat();
  }

  void heartbeat_loop() {
    std::unique_lock<std::mutex> lock(stop_mutex);
    // A periodic timer (the heartbeat contract), not synchronisation.
    while (!stop_cv.wait_for(lock, timing.heartbeat, [&] { return stopping; })) {
      lock.unlock();
      beat();
      lock.lock();
    }
  }

  qos::Timing timing;
  core::Service topic_service = core::Service::MaterialLoad;
  core::SubType topic_side = core::SubType::Request;
  dds::detail::Participant participant;
  std::unique_ptr<dds::detail::Topic> topic;
  std::unique_ptr<dds::detail::Publisher> publisher;
  Listener listener;
  std::unique_ptr<dds::detail::Writer<idl::InteractionSample>> writer;
  std::unique_ptr<dds::detail::HeartbeatWriter> heartbeat;
  std::mutex mutex;
  idl::InteractionSample sample;

  std::mutex seen_mutex;
  std::condition_variable seen_cv;
  std::vector<core::InteractionState> seen;  // every change, in order
  std::size_t next_seen = 0;                 // first one not yet waited for
  std::unique_ptr<dds::DomainObserver> observer;

  std::mutex stop_mutex;
  std::condition_variable stop_cv;
  bool stopping = false;
  std::thread heartbeat_thread;
};

RoguePeer::RoguePeer(int domain, const std::string& device, const std::string& interface_id,
                     core::Service service, core::SubType own_side, const std::string& counterpart)
    : impl_(std::make_unique<Impl>(domain, device, rogue_timing())) {
  auto& i = *impl_;
  fdds::TypeSupport type = idl::type_support<idl::InteractionSamplePubSubType>();
  i.participant.register_type(type);
  const bool request = own_side == core::SubType::Request;
  i.topic_service = service;
  i.topic_side = own_side;
  i.topic = std::make_unique<dds::detail::Topic>(
      i.participant, dds::detail::topics::interaction_topic(own_side, service),
      type.get_type_name(), qos::fastdds_topic_qos(qos::state_topic(i.timing)));
  i.publisher = std::make_unique<dds::detail::Publisher>(
      i.participant, std::vector<std::string>{dds::detail::topics::device_partition(device)});
  i.writer = std::make_unique<dds::detail::Writer<idl::InteractionSample>>(
      *i.publisher, *i.topic, qos::fastdds_writer_qos(qos::state_topic(i.timing)), i.listener);
  i.heartbeat = std::make_unique<dds::detail::HeartbeatWriter>(i.participant, *i.publisher, device,
                                                               0, i.timing);
  i.sample.device_uuid(device);
  i.sample.data_item_id(dds::detail::topics::interaction_item_id(interface_id, service, own_side));
  i.sample.interface_id(interface_id);
  // Paired as the runtime would be: a requester goes ACTIVE only toward a
  // response that names it (the counterpart's interface has our id).
  i.sample.paired_device_uuid(counterpart);
  i.sample.paired_interface_id(interface_id);
  i.sample.service(dds::detail::topics::to_idl(service));
  i.sample.sub_type(dds::detail::topics::to_idl(own_side));
  i.sample.state(dds::detail::topics::to_idl(core::InteractionState::NotReady));

  const auto wanted = request ? core::SubType::Response : core::SubType::Request;
  dds::DomainObserverOptions options;
  options.domain_id = domain;
  options.device_filter = {counterpart};
  options.transport = qos::Transport::LoopbackUdp;
  options.timing = i.timing;
  dds::DomainObserverCallbacks callbacks;
  callbacks.on_value = [&i, service, wanted](const dds::ObservedValue& v) {
    if (v.service != service || v.sub_type != wanted) {
      return;
    }
    const auto parsed = v.state.interaction();
    if (!parsed) {
      return;
    }
    {
      std::lock_guard<std::mutex> lock(i.seen_mutex);
      if (i.seen.empty() || i.seen.back() != *parsed) {
        i.seen.push_back(*parsed);
      }
    }
    i.seen_cv.notify_all();
  };
  i.observer = std::make_unique<dds::DomainObserver>(options, std::move(callbacks));
  i.publish();
  i.beat();
  i.heartbeat_thread = std::thread([&i] { i.heartbeat_loop(); });
}

RoguePeer::~RoguePeer() {
  {
    std::lock_guard<std::mutex> lock(impl_->stop_mutex);
    impl_->stopping = true;
  }
  impl_->stop_cv.notify_all();
  impl_->heartbeat_thread.join();
}

void RoguePeer::set_state(core::InteractionState state) {
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->sample.state(dds::detail::topics::to_idl(state));
  }
  impl_->publish();
}

void RoguePeer::set_raw_state(std::int32_t raw) {
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->sample.state(static_cast<idl::interaction_state::Value>(raw));
  }
  impl_->publish();
}

void RoguePeer::set_raw_service(std::int32_t raw) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->sample.service(static_cast<idl::services::Service>(raw));
}

void RoguePeer::set_service(core::Service service) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->sample.service(dds::detail::topics::to_idl(service));
}

void RoguePeer::set_next_sequence(std::uint64_t next, core::InteractionState state) {
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->sample.sequence_number(next - 1);  // publish() counts one up
    impl_->sample.state(dds::detail::topics::to_idl(state));
  }
  impl_->publish();
}

bool RoguePeer::wait_counterpart(core::InteractionState state, std::chrono::milliseconds timeout) {
  auto& i = *impl_;
  std::unique_lock<std::mutex> lock(i.seen_mutex);
  return i.seen_cv.wait_for(lock, timeout, [&] {
    for (; i.next_seen < i.seen.size(); ++i.next_seen) {
      if (i.seen[i.next_seen] == state) {
        ++i.next_seen;
        return true;
      }
    }
    return false;
  });
}

}  // namespace mtc::test
