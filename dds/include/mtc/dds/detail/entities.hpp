// Internal: RAII wrappers around Fast DDS entities, used by the runtime's
// sources, tests and raw peers (never by a public header). Each wrapper deletes its entity in
// its destructor (destroy children before parents: declare them after their
// parent); Participant's destructor also deletes whatever is left with
// delete_contained_entities(). Destructors never throw: a failed deletion is
// reported on stderr. Every creation failure throws mtc::dds::Error.
//
// Writers always get a DataWriterListener: Fast DDS 2.9.1 crashes when an
// offered-deadline miss reaches a Publisher/Participant listener of a writer
// without one.
#pragma once

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <string>
#include <vector>

#include "mtc/dds/error.hpp"
#include "mtc/qos/participant.hpp"

namespace mtc::dds::detail {

namespace fdds = eprosima::fastdds::dds;

// qos::participant_qos(), with a bad configuration (timing, security
// directory) as a ConfigError.
fdds::DomainParticipantQos checked_qos(const qos::ParticipantConfig& config);

class Participant {
 public:
  // A refused participant is a CreationError; with DDS-Security it names the
  // security directory whose files Fast DDS refused. A loopback participant
  // listens for discovery on the domain's lowest free port
  // (qos::anchor_discovery_port), however many participants the process made.
  Participant(int domain_id, const fdds::DomainParticipantQos& qos);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  // Registers a type (once per name; repeated calls are no-ops).
  void register_type(const fdds::TypeSupport& type);
  fdds::DomainParticipant& get() const noexcept { return *participant_; }

 private:
  fdds::DomainParticipant* participant_ = nullptr;
};

class Topic {
 public:
  Topic(Participant& participant, const std::string& name, const std::string& type_name,
        const fdds::TopicQos& qos);
  ~Topic();
  Topic(const Topic&) = delete;
  Topic& operator=(const Topic&) = delete;
  fdds::Topic& get() const noexcept { return *topic_; }

 private:
  Participant& participant_;
  fdds::Topic* topic_ = nullptr;
};

class Publisher {
 public:
  Publisher(Participant& participant, const std::vector<std::string>& partitions);
  ~Publisher();
  Publisher(const Publisher&) = delete;
  Publisher& operator=(const Publisher&) = delete;
  fdds::Publisher& get() const noexcept { return *publisher_; }
  // Announces every writer of this publisher again under the same GUID and
  // returns how many. Fast DDS 2.9.1 never re-sends an endpoint announcement
  // a remote participant acknowledged before it dropped us, unless that
  // participant's first request after rediscovery wins a race with our
  // discovery heartbeat (docs/multihost.md, "Cable pull"): a fresh
  // announcement makes the oldest one in our discovery history newer than
  // anything it acknowledged, so it gets every announcement again. Setting
  // the publisher's own QoS again does that for each writer (peers see a QoS
  // update, not a new match) and writes no writer state, unlike
  // DataWriter::set_qos, which may race a write on another thread.
  std::size_t reannounce();

 private:
  Participant& participant_;
  fdds::Publisher* publisher_ = nullptr;
};

class Subscriber {
 public:
  Subscriber(Participant& participant, const std::vector<std::string>& partitions);
  ~Subscriber();
  Subscriber(const Subscriber&) = delete;
  Subscriber& operator=(const Subscriber&) = delete;
  fdds::Subscriber& get() const noexcept { return *subscriber_; }
  // Publisher::reannounce for every reader of this subscriber.
  std::size_t reannounce();

 private:
  Participant& participant_;
  fdds::Subscriber* subscriber_ = nullptr;
};

// Untyped writer; Writer<T> below adds the sample type.
class WriterBase {
 public:
  // `listener` is mandatory (see the file comment) and must outlive the writer.
  WriterBase(Publisher& publisher, Topic& topic, const fdds::DataWriterQos& qos,
             fdds::DataWriterListener& listener);
  ~WriterBase();
  WriterBase(const WriterBase&) = delete;
  WriterBase& operator=(const WriterBase&) = delete;

  void assert_liveliness();
  fdds::DataWriter& get() const noexcept { return *writer_; }

 protected:
  void write_untyped(void* sample, const char* what);
  void dispose_untyped(void* sample, const char* what);

 private:
  Publisher& publisher_;
  fdds::DataWriter* writer_ = nullptr;
};

template <typename T>
class Writer : public WriterBase {
 public:
  using WriterBase::WriterBase;
  void write(const T& sample) { write_untyped(const_cast<T*>(&sample), "write"); }
  void dispose(const T& sample) { dispose_untyped(const_cast<T*>(&sample), "dispose"); }
};

class Reader {
 public:
  // `listener` may be null; when set it must outlive the reader.
  Reader(Subscriber& subscriber, Topic& topic, const fdds::DataReaderQos& qos,
         fdds::DataReaderListener* listener,
         const fdds::StatusMask& mask = fdds::StatusMask::all());
  ~Reader();
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;
  fdds::DataReader& get() const noexcept { return *reader_; }

 private:
  Subscriber& subscriber_;
  fdds::DataReader* reader_ = nullptr;
};

}  // namespace mtc::dds::detail
