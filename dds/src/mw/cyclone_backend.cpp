// The Cyclone DDS backend of mw::Participant: participant, topics, publisher
// and writers (the tap is cyclone_tap.cpp).
#include "cyclone_backend.hpp"

#include <ifaddrs.h>
#include <net/if.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <filesystem>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>
#include <type_traits>
#include <vector>

#include "cyclone_entities.hpp"
#include "cyclone_samples.hpp"
#include "mtc/dds/detail/topic_names.hpp"
#include "mtc/qos/cyclone_qos.hpp"
#include "mtc/qos/presets.hpp"
#include "write_batch.hpp"

namespace mtc::dds::mw {

static_assert(std::is_same_v<dds_entity_t, int>, "cyclone_backend.hpp passes entities as int");

namespace {

using cyclone::check;
using cyclone::Entity;

// Cut at the bound and always terminated, as cyclone_samples.cpp does.
template <std::size_t N>
void put_key(char (&to)[N], const std::string& from) {
  const auto n = std::min(from.size(), N - 1);
  std::copy_n(from.data(), n, to);
  std::fill(to + n, to + N, '\0');
}

void flush_writer(std::int64_t handle) noexcept {
  dds_write_flush(static_cast<dds_entity_t>(handle));
}

// Our domains hold what a writer writes (WriteBatch, see domain_recipe):
// sent now, or with the rest of the thread's burst when its WriteBatch ends.
void send(dds_entity_t writer) {
  if (!WriteBatch::defer(&flush_writer, writer)) dds_write_flush(writer);
}

// The writers of one publisher, for wait_for_acknowledgments: Cyclone 0.10
// waits per writer only (a publisher answers UNSUPPORTED).
class WriterList {
 public:
  void add(dds_entity_t w) {
    const std::lock_guard<std::mutex> lock(mutex_);
    writers_.push_back(w);
  }
  void remove(dds_entity_t w) {
    const std::lock_guard<std::mutex> lock(mutex_);
    writers_.erase(std::remove(writers_.begin(), writers_.end(), w), writers_.end());
  }
  std::vector<dds_entity_t> snapshot() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return writers_;
  }

 private:
  mutable std::mutex mutex_;
  std::vector<dds_entity_t> writers_;
};

// A writer entity listed with its publisher while it lives.
class ListedWriter {
 public:
  ListedWriter(dds_entity_t publisher, dds_entity_t topic, const qos::EndpointQos& q,
               WriterList& list)
      : writer_(dds_create_writer(publisher, topic, qos::cyclone_writer_qos(q).get(), nullptr),
                "dds_create_writer"),
        list_(list) {
    list_.add(writer_.get());
  }
  ~ListedWriter() { list_.remove(writer_.get()); }
  ListedWriter(const ListedWriter&) = delete;
  ListedWriter& operator=(const ListedWriter&) = delete;
  ListedWriter(ListedWriter&&) = delete;
  ListedWriter& operator=(ListedWriter&&) = delete;
  dds_entity_t get() const noexcept { return writer_.get(); }

 private:
  Entity writer_;
  WriterList& list_;
};

// A state-sample writer; the C samples have fixed-size strings, so a write
// allocates nothing.
template <typename Sample>
class CycloneValueWriter final : public ValueWriter {
 public:
  CycloneValueWriter(dds_entity_t publisher, dds_entity_t topic, const qos::EndpointQos& q,
                     WriterList& list)
      : writer_(publisher, topic, q, list) {}
  void write(const ObservedValue& value, const ParticipantKey& paired) override {
    Sample s{};
    cyclone::to_c(value, paired, s);
    check(dds_write(writer_.get(), &s), "dds_write (state sample)");
    send(writer_.get());
  }
  void dispose(const std::string& device_uuid, const std::string& data_item_id) override {
    Sample s{};
    put_key(s.device_uuid, device_uuid);
    put_key(s.data_item_id, data_item_id);
    check(dds_dispose(writer_.get(), &s), "dds_dispose (state sample)");
    send(writer_.get());
  }

 private:
  ListedWriter writer_;
};

// Heartbeats are written by one thread; the sample and its sequence buffer
// are kept from write to write.
class CycloneHeartbeatWriter final : public HeartbeatWriter {
 public:
  CycloneHeartbeatWriter(dds_entity_t publisher, dds_entity_t topic, const qos::EndpointQos& q,
                         WriterList& list)
      : writer_(publisher, topic, q, list) {}
  void write(const ObservedHeartbeat& heartbeat) override {
    cyclone::to_c(heartbeat, sample_);
    check(dds_write(writer_.get(), &sample_.sample), "dds_write (heartbeat)");
    send(writer_.get());
  }
  void dispose(const std::string& device_uuid, std::uint32_t group) override {
    mtc_idl_Heartbeat h{};
    put_key(h.device_uuid, device_uuid);
    h.group = group;
    check(dds_dispose(writer_.get(), &h), "dds_dispose (heartbeat)");
    send(writer_.get());
  }

 private:
  ListedWriter writer_;
  cyclone::CycloneHeartbeat sample_;
};

class CycloneDeviceWriter final : public DeviceWriter {
 public:
  CycloneDeviceWriter(dds_entity_t publisher, dds_entity_t topic, const qos::EndpointQos& q,
                      WriterList& list)
      : writer_(publisher, topic, q, list) {}
  void write(const ObservedDevice& device, std::uint64_t sequence_number,
             std::int64_t source_time_ns) override {
    cyclone::CycloneDevice d;
    cyclone::to_c(device, sequence_number, source_time_ns, d);
    check(dds_write(writer_.get(), &d.sample), "dds_write (device announcement)");
    send(writer_.get());
  }
  void dispose(const std::string& device_uuid) override {
    mtc_idl_DeviceDescription d{};
    put_key(d.device_uuid, device_uuid);
    check(dds_dispose(writer_.get(), &d), "dds_dispose (device announcement)");
    send(writer_.get());
  }

 private:
  ListedWriter writer_;
};

class CyclonePublisher final : public Publisher {
 public:
  CyclonePublisher(dds_entity_t participant, CycloneTopics& topics,
                   const std::vector<std::string>& partitions)
      : topics_(topics),
        publisher_(dds_create_publisher(participant, qos::cyclone_partition_qos(partitions).get(),
                                        nullptr),
                   "dds_create_publisher") {}

  std::unique_ptr<ValueWriter> value_writer(TopicKind kind, std::size_t interaction,
                                            const qos::EndpointQos& q) override {
    const auto p = publisher_.get();
    switch (kind) {
      case TopicKind::Request:
      case TopicKind::Response:
        return std::make_unique<CycloneValueWriter<mtc_idl_InteractionSample>>(
            p, topics_.interaction_topic(interaction), q, writers_);
      case TopicKind::InterfaceState:
        return std::make_unique<CycloneValueWriter<mtc_idl_InterfaceStateSample>>(
            p, topics_.topic(kind), q, writers_);
      case TopicKind::DoorState:
        return std::make_unique<CycloneValueWriter<mtc_idl_DoorStateSample>>(p, topics_.topic(kind),
                                                                             q, writers_);
      case TopicKind::ChuckState:
        return std::make_unique<CycloneValueWriter<mtc_idl_ChuckStateSample>>(
            p, topics_.topic(kind), q, writers_);
      case TopicKind::DeviceDescription:
      case TopicKind::Heartbeat:
        break;
    }
    throw ConfigError(std::string("mw::Publisher: ") + detail::topic_name(kind) +
                      " carries no state samples");
  }
  std::unique_ptr<HeartbeatWriter> heartbeat_writer(const qos::EndpointQos& q) override {
    return std::make_unique<CycloneHeartbeatWriter>(
        publisher_.get(), topics_.topic(TopicKind::Heartbeat), q, writers_);
  }
  std::unique_ptr<DeviceWriter> device_writer(const qos::EndpointQos& q) override {
    return std::make_unique<CycloneDeviceWriter>(
        publisher_.get(), topics_.topic(TopicKind::DeviceDescription), q, writers_);
  }
  // Cyclone re-announces endpoints to a participant it rediscovers by itself.
  std::size_t reannounce() override { return 0; }
  bool wait_for_acknowledgments(std::chrono::nanoseconds bound) override {
    const auto end = std::chrono::steady_clock::now() + bound;
    const auto writers = writers_.snapshot();
    return std::all_of(writers.begin(), writers.end(), [end](dds_entity_t w) {
      const auto left = std::max(std::chrono::nanoseconds(0),
                                 std::chrono::duration_cast<std::chrono::nanoseconds>(
                                     end - std::chrono::steady_clock::now()));
      const dds_return_t rc = dds_wait_for_acks(w, left.count());
      return rc != DDS_RETCODE_TIMEOUT && check(rc, "dds_wait_for_acks") >= 0;
    });
  }

 private:
  CycloneTopics& topics_;
  Entity publisher_;
  WriterList writers_;  // emptied by the writers, which go before the publisher
};

// The host's IPv4 interfaces that are up, can multicast and are not the
// loopback: what Fast DDS's built-in UDP transport sends on, and so what a
// Cyclone participant on the network transport must listen on to meet it.
std::vector<std::string> multicast_interfaces() {
  ifaddrs* raw = nullptr;
  if (getifaddrs(&raw) != 0) {
    throw ConfigError("cannot list the network interfaces: " +
                      std::error_code(errno, std::generic_category()).message());
  }
  const std::unique_ptr<ifaddrs, void (*)(ifaddrs*)> list(raw, freeifaddrs);
  std::vector<std::string> names;
  for (const ifaddrs* i = list.get(); i != nullptr; i = i->ifa_next) {
    const unsigned wanted = IFF_UP | IFF_MULTICAST;
    if (i->ifa_addr == nullptr || i->ifa_addr->sa_family != AF_INET) continue;
    if ((i->ifa_flags & wanted) != wanted || (i->ifa_flags & IFF_LOOPBACK) != 0) continue;
    if (std::find(names.begin(), names.end(), i->ifa_name) == names.end()) {
      names.emplace_back(i->ifa_name);
    }
  }
  return names;
}

// Every transport but Fast DDS's fault-injecting test transport. The
// network transport's recipe is its configuration with no interface named:
// the interfaces are the host's, read when the domain is made
// (cyclone::DomainRecipe). Security is the participant's, not the domain's
// (participant_qos below).
// Appended to the domain's configuration (Cyclone merges the fragments):
// writers hold their samples until send() flushes them, so that a burst
// leaves as one message per writer (WriteBatch).
constexpr const char* kHoldWrites =
    ",<CycloneDDS><Domain Id=\"any\"><Internal><WriteBatch>true</WriteBatch></Internal>"
    "</Domain></CycloneDDS>";

cyclone::DomainRecipe domain_recipe(const qos::ParticipantConfig& config) {
  try {
    switch (config.transport) {
      case qos::Transport::Loopback:
      case qos::Transport::LoopbackUdp: {
        auto xml = qos::cyclone_loopback_config(config.timing) + kHoldWrites;
        return {xml, [xml] { return xml; }};
      }
      case qos::Transport::Network: {
        const qos::Timing timing = config.timing;
        return {"network " + qos::cyclone_network_config(timing, {}) + kHoldWrites, [timing] {
                  try {
                    return qos::cyclone_network_config(timing, multicast_interfaces()) +
                           kHoldWrites;
                  } catch (const std::invalid_argument& e) {
                    throw ConfigError(e.what());
                  }
                }};
      }
      case qos::Transport::LoopbackTest:
        break;
    }
  } catch (const std::invalid_argument& e) {
    throw ConfigError(e.what());
  }
  throw ConfigError(std::string("the Cyclone DDS backend has no '") +
                    std::string(qos::to_string(config.transport)) +
                    "' transport (it injects faults into Fast DDS's transports)");
}

// DDS-Security: the directory is checked first, so that a bad file is named
// (Cyclone only logs why it refused a participant), then handed to Cyclone's
// builtin plugins by absolute path. No security: Cyclone's default QoS.
qos::CycloneQos participant_qos(const qos::ParticipantConfig& config) {
  if (config.security_dir.empty()) return nullptr;
  if (auto problem = qos::check_security_dir(config.security_dir)) throw ConfigError(*problem);
  std::error_code ec;
  const auto dir = std::filesystem::canonical(config.security_dir, ec);
  return qos::cyclone_security_qos(ec ? config.security_dir : dir.string(),
                                   qos::cyclone_security_plugin_dir());
}

dds_entity_t create_participant(int domain_id, const qos::ParticipantConfig& config) {
  const auto qos = participant_qos(config);
  const dds_entity_t participant =
      dds_create_participant(static_cast<dds_domainid_t>(domain_id), qos.get(), nullptr);
  // The files passed the pre-flight check, so Cyclone disliked their
  // content (a grant for another subject, a domain id above 230), or its
  // plugins did not load: its log line above says which.
  if (participant < 0 && qos) {
    throw CreationError("dds_create_participant(domain " + std::to_string(domain_id) +
                        "): Cyclone DDS refused the DDS-Security files in " + config.security_dir +
                        " (" + dds_strretcode(participant) + "; plugins from '" +
                        qos::cyclone_security_plugin_dir() + "': see the security log above)");
  }
  return participant;
}

class CycloneParticipant final : public Participant, public CycloneTopics {
 public:
  CycloneParticipant(int domain_id, const qos::ParticipantConfig& config)
      : timing_(config.timing),
        domain_(
            cyclone::acquire_domain(static_cast<dds_domainid_t>(domain_id), domain_recipe(config))),
        participant_(create_participant(domain_id, config), "dds_create_participant") {}

  ParticipantKey key() const override {
    dds_guid_t guid;
    check(dds_get_guid(participant_.get(), &guid), "dds_get_guid");
    ParticipantKey out{};
    std::copy_n(guid.v, out.size(), out.begin());
    return out;
  }
  Middleware middleware() const noexcept override { return Middleware::Cyclone; }
  std::unique_ptr<Publisher> publisher(const std::vector<std::string>& partitions) override {
    return std::make_unique<CyclonePublisher>(participant_.get(), *this, partitions);
  }
  std::unique_ptr<Tap> tap(const TapConfig& config, TapSink sink) override {
    return make_cyclone_tap(participant_.get(), *this, config, std::move(sink));
  }

  int topic(TopicKind kind) override;
  int interaction_topic(std::size_t index) override;

 private:
  Entity make_topic(const dds_topic_descriptor_t& type, const std::string& name,
                    const qos::EndpointQos& q) {
    return Entity(dds_create_topic(participant_.get(), &type, name.c_str(),
                                   qos::cyclone_topic_qos(q).get(), nullptr),
                  "dds_create_topic");
  }

  qos::Timing timing_;
  std::shared_ptr<cyclone::Domain> domain_;
  Entity participant_;
  std::mutex topics_mutex_;  // publishers and taps may be made on several threads
  std::array<Entity, detail::kTopicKindCount> topics_;
  std::array<Entity, detail::kInteractionTopicCount> interactions_;
};

int CycloneParticipant::topic(TopicKind kind) {
  const std::lock_guard<std::mutex> lock(topics_mutex_);
  auto& slot = topics_.at(static_cast<std::size_t>(kind));
  if (slot) return slot.get();
  const std::string name = detail::topic_name(kind);
  switch (kind) {
    case TopicKind::Request:
    case TopicKind::Response:
      throw ConfigError("mw::CycloneTopics: " + name + " is one topic per service");
    case TopicKind::InterfaceState:
      slot = make_topic(mtc_idl_InterfaceStateSample_desc, name, qos::state_topic(timing_));
      break;
    case TopicKind::DoorState:
      slot = make_topic(mtc_idl_DoorStateSample_desc, name, qos::state_topic(timing_));
      break;
    case TopicKind::ChuckState:
      slot = make_topic(mtc_idl_ChuckStateSample_desc, name, qos::state_topic(timing_));
      break;
    case TopicKind::DeviceDescription:
      slot =
          make_topic(mtc_idl_DeviceDescription_desc, name, qos::device_description_topic(timing_));
      break;
    case TopicKind::Heartbeat:
      slot = make_topic(mtc_idl_Heartbeat_desc, name, qos::heartbeat_topic(timing_));
      break;
  }
  return slot.get();
}

int CycloneParticipant::interaction_topic(std::size_t index) {
  const std::lock_guard<std::mutex> lock(topics_mutex_);
  auto& slot = interactions_.at(index);
  if (!slot) {
    slot = make_topic(mtc_idl_InteractionSample_desc, detail::interaction_topic_name(index),
                      qos::state_topic(timing_));
  }
  return slot.get();
}

}  // namespace

std::unique_ptr<Participant> make_cyclone_participant(int domain_id,
                                                      const qos::ParticipantConfig& config) {
  return std::make_unique<CycloneParticipant>(domain_id, config);
}

}  // namespace mtc::dds::mw
