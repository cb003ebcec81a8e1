#include "mtc/dds/detail/entities.hpp"

#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>

#include <algorithm>
#include <cstddef>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <iostream>
#include <memory>

#include "mtc/dds/detail/return_code.hpp"
#include "mtc/qos/participant_qos.hpp"
#include "mtc/qos/shared_memory.hpp"

namespace mtc::dds::detail {

namespace {

// Destructors must not throw; a failed deletion is worth a line on stderr
// (the participant's delete_contained_entities cleans up anyway).
void report(const ReturnCode& code, const char* what) {
  if (code != ReturnCode::RETCODE_OK) {
    std::cerr << "mtc::dds: " << what << " failed: " << detail::return_code_name(code) << '\n';
  }
}

// Throws for a failed write or dispose, naming the topic. The text is built
// only then: a write is on every transit's path, and building it first cost
// four allocations per sample.
void check_sample_call(const ReturnCode& code, const char* what, const fdds::DataWriter& writer) {
  if (code != ReturnCode::RETCODE_OK) {
    check(code, std::string(what) + " on " + writer.get_topic()->get_name());
  }
}

// The builtin transports include shared memory, and so may a user's list.
bool uses_shared_memory(const fdds::DomainParticipantQos& qos) {
  const auto& transport = qos.transport();
  if (transport.use_builtin_transports) return true;
  return std::any_of(
      transport.user_transports.begin(), transport.user_transports.end(), [](const auto& t) {
        return std::dynamic_pointer_cast<eprosima::fastdds::rtps::SharedMemTransportDescriptor>(
                   t) != nullptr;
      });
}

}  // namespace

Participant::Participant(int domain_id, const fdds::DomainParticipantQos& qos) {
  // A process SIGKILLed on this host left its segments in /dev/shm for good
  // (Fast DDS never looks at them again): remove the dead ones before
  // adding our own (qos/shared_memory.hpp; issue 10).
  if (uses_shared_memory(qos)) qos::remove_stale_shared_memory_once();
  fdds::DomainParticipantQos anchored = qos;
  qos::anchor_discovery_port(anchored, domain_id);
  participant_ = qos::create_participant(domain_id, anchored);
  if (participant_ == nullptr) {
    const std::string what = "create_participant(domain " + std::to_string(domain_id) + ")";
    const std::string security_dir = qos::security_dir_of(qos);
    if (security_dir.empty()) throw CreationError(what);
    // The files passed the pre-flight check (qos::check_security_dir), so
    // Fast DDS disliked their content: its log line above says what.
    throw CreationError(what + ": Fast DDS refused the DDS-Security files in " + security_dir +
                        " (a permissions grant for another subject, an invalid governance or "
                        "permissions document: see the security log above)");
  }
}

fdds::DomainParticipantQos checked_qos(const qos::ParticipantConfig& config) {
  try {
    return qos::participant_qos(config);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(e.what());
  }
}

Participant::~Participant() {
  report(participant_->delete_contained_entities(), "delete_contained_entities");
  report(fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_),
         "delete_participant");
}

void Participant::register_type(const fdds::TypeSupport& type) {
  if (participant_->find_type(type.get_type_name()).empty()) {
    const std::string& name = type.get_type_name();
    check(type.register_type(participant_), "register_type " + name);
  }
}

Topic::Topic(Participant& participant, const std::string& name, const std::string& type_name,
             const fdds::TopicQos& qos)
    : participant_(participant) {
  topic_ = participant.get().create_topic(name, type_name, qos);
  if (topic_ == nullptr) {
    throw CreationError("create_topic " + name + " (" + type_name + ")");
  }
}

Topic::~Topic() {
  report(participant_.get().delete_topic(topic_), "delete_topic");
}

namespace {

fdds::PartitionQosPolicy partition_policy(const std::vector<std::string>& partitions) {
  fdds::PartitionQosPolicy policy;
  for (const auto& p : partitions) {
    policy.push_back(p.c_str());
  }
  return policy;
}

}  // namespace

Publisher::Publisher(Participant& participant, const std::vector<std::string>& partitions)
    : participant_(participant) {
  fdds::PublisherQos qos = fdds::PUBLISHER_QOS_DEFAULT;
  qos.partition(partition_policy(partitions));
  publisher_ = participant.get().create_publisher(qos);
  if (publisher_ == nullptr) {
    throw CreationError("create_publisher");
  }
}

Publisher::~Publisher() {
  report(participant_.get().delete_publisher(publisher_), "delete_publisher");
}

std::size_t Publisher::reannounce() {
  const fdds::PublisherQos same = publisher_->get_qos();  // a copy, not the one it assigns
  check(publisher_->set_qos(same), "re-announce the writers (Publisher::set_qos)");
  std::vector<fdds::DataWriter*> writers;
  publisher_->get_datawriters(writers);
  return writers.size();
}

Subscriber::Subscriber(Participant& participant, const std::vector<std::string>& partitions)
    : participant_(participant) {
  fdds::SubscriberQos qos = fdds::SUBSCRIBER_QOS_DEFAULT;
  qos.partition(partition_policy(partitions));
  subscriber_ = participant.get().create_subscriber(qos);
  if (subscriber_ == nullptr) {
    throw CreationError("create_subscriber");
  }
}

Subscriber::~Subscriber() {
  report(participant_.get().delete_subscriber(subscriber_), "delete_subscriber");
}

std::size_t Subscriber::reannounce() {
  const fdds::SubscriberQos same = subscriber_->get_qos();  // a copy, not the one it assigns
  check(subscriber_->set_qos(same), "re-announce the readers (Subscriber::set_qos)");
  std::vector<fdds::DataReader*> readers;
  check(subscriber_->get_datareaders(readers), "get_datareaders");
  return readers.size();
}

WriterBase::WriterBase(Publisher& publisher, Topic& topic, const fdds::DataWriterQos& qos,
                       fdds::DataWriterListener& listener)
    : publisher_(publisher) {
  writer_ = publisher.get().create_datawriter(&topic.get(), qos, &listener);
  if (writer_ == nullptr) {
    throw CreationError("create_datawriter " + topic.get().get_name());
  }
}

WriterBase::~WriterBase() {
  // Fast DDS 2.9 deletes a writer by releasing its samples one at a time
  // while the writer's periodic heartbeat still runs, and each heartbeat
  // walks every hole of the history under the same lock: with thousands of
  // instances (128 interfaces, observed) deleting one writer was seen to
  // take minutes. clear_history releases them all under one hold of that
  // lock first. What it drops was acknowledged or waited for in vain
  // (Equipment's shutdown waits for acknowledgments first), and deleting
  // the writer would drop it too.
  std::size_t removed = 0;
  report(writer_->clear_history(&removed), "clear_history");
  report(publisher_.get().delete_datawriter(writer_), "delete_datawriter");
}

void WriterBase::assert_liveliness() {
  check(writer_->assert_liveliness(), "assert_liveliness");
}

void WriterBase::write_untyped(void* sample, const char* what) {
  check_sample_call(writer_->write(sample, fdds::HANDLE_NIL), what, *writer_);
}

void WriterBase::dispose_untyped(void* sample, const char* what) {
  check_sample_call(writer_->dispose(sample, fdds::HANDLE_NIL), what, *writer_);
}

Reader::Reader(Subscriber& subscriber, Topic& topic, const fdds::DataReaderQos& qos,
               fdds::DataReaderListener* listener, const fdds::StatusMask& mask)
    : subscriber_(subscriber),
      reader_(subscriber.get().create_datareader(&topic.get(), qos, listener, mask)) {
  if (reader_ == nullptr) {
    throw CreationError("create_datareader " + topic.get().get_name());
  }
}

Reader::~Reader() {
  report(subscriber_.get().delete_datareader(reader_), "delete_datareader");
}

}  // namespace mtc::dds::detail
