#include "raw_pingpong.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <fastdds/dds/core/condition/WaitSet.hpp>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <functional>
#include <iostream>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "mtc/bench/proc_cpu.hpp"
#include "mtc/idl/mtconnect_interfacesPubSubTypes.h"
#include "mtc/idl/type_support.hpp"
#include "mtc/qos/fastdds_qos.hpp"
#include "mtc/qos/participant_qos.hpp"
#include "mtc/qos/presets.hpp"

namespace mtc::bench {
namespace {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastrtps::types::ReturnCode_t;

constexpr const char* kPingTopic = "mtc_bench_ping";
constexpr const char* kPongTopic = "mtc_bench_pong";

[[noreturn]] void cannot_create(const char* what) {
  throw std::runtime_error(std::string("fast dds: cannot create ") + what);
}

// Small enough for the shallow static analyzer to inline, so it knows that
// nothing after a failed check runs.
void check(bool ok, const char* what) {
  if (!ok) cannot_create(what);
}

void check_rc(ReturnCode_t rc, const char* what) {
  if (rc != ReturnCode_t::RETCODE_OK) {
    throw std::runtime_error(std::string("fast dds: ") + what + " failed, code " +
                             std::to_string(rc()));
  }
}

// Fast DDS 2.9 can crash when a writer status is routed to a publisher
// listener while the writer has none (FASTDDS-NOTES): every writer gets one.
class QuietWriterListener : public fdds::DataWriterListener {};

// One participant with a writer on one topic and a reader on the other.
// Owns every entity; the destructor tears them down in DDS order.
class Endpoint {
 public:
  // With a `listener`, data is taken on Fast DDS's receive thread and the
  // WaitSet stays unused.
  Endpoint(const PingPongOptions& options, const char* name, const char* write_topic,
           const char* read_topic, fdds::DataReaderListener* listener = nullptr) {
    // The project's own presets: the participant QoS of its loopback
    // transports and the QoS of its state topics (RELIABLE, TRANSIENT_LOCAL,
    // KEEP_LAST 1, changes only; see mtc/qos/presets.hpp).
    mtc::qos::ParticipantConfig pc;
    pc.name = name;
    pc.transport = options.transport == Transport::ShmUdp ? mtc::qos::Transport::Loopback
                                                          : mtc::qos::Transport::LoopbackUdp;
    const fdds::DomainParticipantQos pqos = mtc::qos::participant_qos(pc);
    const mtc::qos::EndpointQos preset = mtc::qos::state_topic(pc.timing);

    // One at a time, after Fast DDS's type registry (participant_qos.hpp):
    // the one-process series creates both ends at once.
    participant_ = mtc::qos::create_participant(options.domain_id, pqos);
    check(participant_ != nullptr, "participant");
    check_rc(type_.register_type(participant_), "type registration");
    fdds::Topic* wtopic = participant_->create_topic(write_topic, type_.get_type_name(),
                                                     mtc::qos::fastdds_topic_qos(preset));
    fdds::Topic* rtopic = participant_->create_topic(read_topic, type_.get_type_name(),
                                                     mtc::qos::fastdds_topic_qos(preset));
    check(wtopic != nullptr && rtopic != nullptr, "topics");
    fdds::Publisher* pub = participant_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    fdds::Subscriber* sub = participant_->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
    check(pub != nullptr && sub != nullptr, "publisher/subscriber");

    const fdds::DataWriterQos wqos = mtc::qos::fastdds_writer_qos(preset);
    writer_ = pub->create_datawriter(wtopic, wqos, &writer_listener_);
    check(writer_ != nullptr, "writer");

    const fdds::DataReaderQos rqos = mtc::qos::fastdds_reader_qos(preset);
    reader_ = listener == nullptr ? sub->create_datareader(rtopic, rqos)
                                  : sub->create_datareader(rtopic, rqos, listener,
                                                           fdds::StatusMask::data_available());
    check(reader_ != nullptr, "reader");

    reader_->get_statuscondition().set_enabled_statuses(fdds::StatusMask::data_available());
    check_rc(waitset_.attach_condition(reader_->get_statuscondition()), "waitset attach");
  }

  ~Endpoint() {
    reader_->set_listener(nullptr);
    waitset_.detach_condition(reader_->get_statuscondition());
    participant_->delete_contained_entities();
    fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
  }

  Endpoint(const Endpoint&) = delete;
  Endpoint& operator=(const Endpoint&) = delete;

  // Blocks until data may be available or `timeout` passes.
  bool wait_data(std::chrono::milliseconds timeout) {
    fdds::ConditionSeq active;
    const auto secs = static_cast<int32_t>(timeout.count() / 1000);
    const auto nsecs = static_cast<uint32_t>((timeout.count() % 1000) * 1000000);
    return waitset_.wait(active, eprosima::fastrtps::Duration_t(secs, nsecs)) ==
           ReturnCode_t::RETCODE_OK;
  }

  bool take(mtc::idl::InteractionSample& sample) { return take_from(reader_, sample); }

  static bool take_from(fdds::DataReader* reader, mtc::idl::InteractionSample& sample) {
    fdds::SampleInfo info;
    while (reader->take_next_sample(&sample, &info) == ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) {
        return true;
      }
    }
    return false;
  }

  void write(mtc::idl::InteractionSample& sample) {
    if (!writer_->write(&sample)) {
      throw std::runtime_error("fast dds: write failed");
    }
  }

  bool matched() const {
    fdds::PublicationMatchedStatus pub;
    fdds::SubscriptionMatchedStatus sub;
    writer_->get_publication_matched_status(pub);
    reader_->get_subscription_matched_status(sub);
    return pub.current_count > 0 && sub.current_count > 0;
  }

 private:
  fdds::TypeSupport type_ = mtc::idl::type_support<mtc::idl::InteractionSamplePubSubType>();
  QuietWriterListener writer_listener_;
  fdds::DomainParticipant* participant_ = nullptr;
  fdds::DataWriter* writer_ = nullptr;
  fdds::DataReader* reader_ = nullptr;
  fdds::WaitSet waitset_;
};

mtc::idl::InteractionSample make_sample(const char* device) {
  mtc::idl::InteractionSample s;
  s.device_uuid(device);
  s.data_item_id("bench_material_load_request");
  s.interface_id("bench_material_handler");
  s.service(mtc::idl::services::MATERIAL_LOAD);
  s.sub_type(mtc::idl::sub_types::REQUEST);
  s.state(mtc::idl::interaction_state::ACTIVE);
  return s;
}

// Discovery has no event we could wait on through this API without a
// listener; a short poll is fine here, it is outside the timed section.
void wait_matched(const Endpoint& ep, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!ep.matched()) {
    if (std::chrono::steady_clock::now() > deadline) {
      throw std::runtime_error("pinger: ponger not discovered in time");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

// The ponger's echo budget (PingPongOptions::echo_limit), shared by the
// receive thread that echoes and the thread that waits for the end.
class EchoBudget {
 public:
  explicit EchoBudget(const PingPongOptions& options)
      : limit_(options.echo_limit), on_limit_(options.on_echo_limit) {}

  // Before each echo: false once `limit_` echoes were sent (on_limit_ runs
  // on the first refusal).
  bool take() {
    if (limit_ == 0) {
      return true;
    }
    const int count = used_.fetch_add(1) + 1;
    if (count <= limit_) {
      return true;
    }
    if (count == limit_ + 1 && on_limit_) {
      on_limit_();
    }
    return false;
  }

  bool spent() const { return limit_ > 0 && used_.load() > limit_; }

 private:
  const int limit_;
  const std::function<void()> on_limit_;
  std::atomic<int> used_{0};
};

// The ponger's echo, written on the receive thread that delivered the ping.
class EchoListener : public fdds::DataReaderListener {
 public:
  explicit EchoListener(EchoBudget& budget) : budget_(budget) {}

  void attach(Endpoint* endpoint) { endpoint_.store(endpoint); }

  void on_data_available(fdds::DataReader* reader) override {
    // A ping can arrive while the Endpoint that owns this reader is still
    // being built (TRANSIENT_LOCAL hands a late ponger the last one): it is
    // left in the reader and echoed with the next ping, which the pinger
    // sends after a stall (UBSan caught the null call once under ASan).
    Endpoint* const endpoint = endpoint_.load();
    if (endpoint == nullptr) return;
    mtc::idl::InteractionSample sample;
    while (Endpoint::take_from(reader, sample)) {
      if (!budget_.take()) {
        return;
      }
      sample.device_uuid("bench-pong");
      endpoint->write(sample);
    }
  }

 private:
  EchoBudget& budget_;
  std::atomic<Endpoint*> endpoint_{nullptr};
};

// The pinger's side of the listener ping-pong: each echo is timed and the
// next ping written on the receive thread; the benchmark thread only waits
// for the end, or for a stall: then it sends the next ping itself, or ends
// the series after give_up_after stalls in a row.
class PingListener : public fdds::DataReaderListener {
 public:
  PingListener(int warmup, int samples, int give_up_after)
      : warmup_(warmup), total_(warmup + samples), give_up_after_(give_up_after) {
    ping_ = make_sample("bench-ping");
  }

  void attach(Endpoint* endpoint) { endpoint_.store(endpoint); }

  void on_data_available(fdds::DataReader* reader) override {
    // Not attached yet (an echo left from before, delivered on match): the
    // series has not started, and run() sends its first ping itself.
    if (endpoint_.load() == nullptr) return;
    mtc::idl::InteractionSample echo;
    while (Endpoint::take_from(reader, echo)) {
      const auto now = std::chrono::steady_clock::now();
      std::lock_guard<std::mutex> lock(mutex_);
      if (given_up_ || echo.sequence_number() != ping_.sequence_number()) {
        continue;  // the echo of a ping already given up on
      }
      stalls_in_a_row_ = 0;
      if (sent_ > warmup_) {
        samples_us_.push_back(to_us(now - sent_at_));
      }
      send_next_locked();
    }
  }

  // Runs the whole series; returns the samples and counts the timed pings
  // that got no echo within `reply_timeout` in `timeouts`, and those not
  // sent at all (the series given up) in `not_run`.
  std::vector<double> run(std::chrono::milliseconds reply_timeout, std::size_t& timeouts,
                          int& not_run) {
    std::unique_lock<std::mutex> lock(mutex_);
    send_next_locked();
    while (sent_ <= total_) {
      const int before = sent_;
      if (done_.wait_for(lock, reply_timeout, [&] { return sent_ != before; })) {
        continue;
      }
      timeouts += sent_ > warmup_ ? 1 : 0;  // lost or late
      if (++stalls_in_a_row_ >= give_up_after_) {
        given_up_ = true;
        not_run = total_ - std::max(sent_, warmup_);
        break;
      }
      send_next_locked();  // go on with the next ping
    }
    return std::move(samples_us_);
  }

 private:
  void send_next_locked() {
    if (sent_ >= total_) {
      ++sent_;  // past the last: run() returns
      done_.notify_all();
      return;
    }
    ++sent_;
    ping_.sequence_number(static_cast<unsigned long long>(sent_));
    sent_at_ = std::chrono::steady_clock::now();
    endpoint_.load()->write(ping_);
    done_.notify_all();
  }

  const int warmup_;
  const int total_;
  const int give_up_after_;
  std::atomic<Endpoint*> endpoint_{nullptr};
  std::mutex mutex_;
  std::condition_variable done_;
  mtc::idl::InteractionSample ping_;
  int sent_ = 0;
  int stalls_in_a_row_ = 0;
  bool given_up_ = false;
  std::chrono::steady_clock::time_point sent_at_;
  std::vector<double> samples_us_;
};

// Ends a series whose ponger stopped answering: says so on stderr and counts
// the `not_run` timed round trips as timeouts, as the equipment series do
// (count + timeouts stays the number of round trips asked for).
void give_up(Series& series, const PingPongOptions& options, int not_run) {
  std::cerr << "raw round trip (" << series.layer << ", " << series.transport
            << "): " << options.give_up_after << " round trips in a row got no echo in "
            << options.reply_timeout.count() << " ms; " << not_run
            << " timed round trips of this series not run\n";
  series.timeouts += static_cast<std::size_t>(not_run);
  series.cpu_us_per_op = -1;  // per round trip of a series cut short: meaningless
}

Series make_series(const PingPongOptions& options) {
  Series series;
  series.layer = options.listener ? "raw_fastdds_listener" : "raw_fastdds";
  series.metric = "round_trip";
  series.transport = to_string(options.transport);
  series.samples_us.reserve(static_cast<std::size_t>(options.samples));
  return series;
}

// The listener ping-pong's pinger: pings and timing on the receive thread.
Series run_listener_pinger(const PingPongOptions& options,
                           std::chrono::milliseconds match_timeout) {
  Series series = make_series(options);
  PingListener pinger(options.warmup, options.samples, options.give_up_after);
  Endpoint ep(options, "mtc_bench_pinger", kPingTopic, kPongTopic, &pinger);
  pinger.attach(&ep);
  wait_matched(ep, match_timeout);
  // The warm-up's CPU is counted too: it is a small share of the run and
  // the receive thread gives no cheaper point to start the count.
  const double cpu0 = cpu_seconds_both(options.peer);
  int not_run = 0;
  series.samples_us = pinger.run(options.reply_timeout, series.timeouts, not_run);
  const double cpu1 = cpu_seconds_both(options.peer);
  series.cpu_us_per_op = (cpu1 - cpu0) * 1e6 / (options.warmup + options.samples);
  if (not_run > 0) {
    give_up(series, options, not_run);
  }
  return series;
}

// Writes `ping` and waits (WaitSet, never longer than the reply timeout in
// all) for its echo; true when it came.
bool round_trip(Endpoint& ep, mtc::idl::InteractionSample& ping,
                std::chrono::milliseconds reply_timeout) {
  const auto seq = ping.sequence_number();
  mtc::idl::InteractionSample echo;
  ep.write(ping);
  const auto deadline = std::chrono::steady_clock::now() + reply_timeout;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0 || !ep.wait_data(left)) {
      return false;
    }
    bool answered = false;
    while (ep.take(echo)) {
      answered = answered || echo.sequence_number() == seq;
    }
    if (answered) {
      return true;
    }
  }
}

// The WaitSet ping-pong's pinger: this thread writes, waits and times.
Series run_waitset_pinger(const PingPongOptions& options, std::chrono::milliseconds match_timeout) {
  Series series = make_series(options);
  Endpoint ep(options, "mtc_bench_pinger", kPingTopic, kPongTopic);
  wait_matched(ep, match_timeout);
  double cpu0 = 0;
  mtc::idl::InteractionSample ping = make_sample("bench-ping");
  const int total = options.warmup + options.samples;
  int timeouts_in_a_row = 0;
  for (int i = 0; i < total; ++i) {
    ping.sequence_number(static_cast<unsigned long long>(i) + 1);
    if (i == options.warmup) {
      cpu0 = cpu_seconds_both(options.peer);
    }
    const auto t0 = std::chrono::steady_clock::now();
    const bool answered = round_trip(ep, ping, options.reply_timeout);
    const auto t1 = std::chrono::steady_clock::now();
    timeouts_in_a_row = answered ? 0 : timeouts_in_a_row + 1;
    if (i >= options.warmup && answered) {
      series.samples_us.push_back(to_us(t1 - t0));
    } else if (i >= options.warmup) {
      ++series.timeouts;
    }
    if (timeouts_in_a_row >= options.give_up_after) {
      give_up(series, options, total - std::max(i + 1, options.warmup));
      return series;
    }
  }
  series.cpu_us_per_op = (cpu_seconds_both(options.peer) - cpu0) * 1e6 / options.samples;
  return series;
}

}  // namespace

std::string to_string(Transport t) {
  return t == Transport::ShmUdp ? "shm_udp" : "udp_loopback";
}

bool parse_transport(const std::string& text, Transport& out) {
  if (text == "udp" || text == "udp_loopback") {
    out = Transport::UdpLoopback;
  } else if (text == "shm" || text == "shm_udp") {
    out = Transport::ShmUdp;
  } else {
    return false;
  }
  return true;
}

void run_ponger(const PingPongOptions& options, const std::atomic<bool>& stop) {
  EchoBudget budget(options);
  if (options.listener) {
    EchoListener echo(budget);
    Endpoint ep(options, "mtc_bench_ponger", kPongTopic, kPingTopic, &echo);
    echo.attach(&ep);
    while (!stop.load() && !budget.spent()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));  // the receive thread echoes
    }
    return;
  }
  Endpoint ep(options, "mtc_bench_ponger", kPongTopic, kPingTopic);
  mtc::idl::InteractionSample sample;
  while (!stop.load() && !budget.spent()) {
    if (!ep.wait_data(std::chrono::milliseconds(100))) {
      continue;
    }
    while (ep.take(sample) && budget.take()) {
      sample.device_uuid("bench-pong");
      ep.write(sample);
    }
  }
}

Series run_pinger(const PingPongOptions& options, std::chrono::milliseconds match_timeout) {
  return options.listener ? run_listener_pinger(options, match_timeout)
                          : run_waitset_pinger(options, match_timeout);
}

}  // namespace mtc::bench
