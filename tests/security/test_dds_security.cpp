// DDS-Security of the runtime (issue 11), with the PKI made by
// scripts/security/make-pki.sh: bad security files are refused naming the
// file; an unauthenticated participant neither sees nor moves the secured
// cell; an authenticated one cannot write what its permissions do not grant;
// the Part 5 handshake and the comms-loss scenario work secured. Intra-process
// delivery is off, so every sample crosses a transport (and its encryption).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "../dds/equipment_fixture.hpp"
#include "mtc/dds/detail/entities.hpp"
#include "mtc/dds/detail/topics.hpp"
#include "mtc/dds/domain_observer.hpp"
#include "mtc/idl/mtconnect_interfacesPubSubTypes.h"
#include "mtc/idl/type_support.hpp"
#include "mtc/qos/fastdds_qos.hpp"
#include "mtc/qos/participant_qos.hpp"
#include "mtc/qos/presets.hpp"
#include "security_pki.hpp"
#include "security_test_helpers.hpp"
#include "transport.hpp"

namespace mtc::dds::testing {
namespace {

using core::InterfaceType;
using core::SubType;
using security_test::Pki;
using security_test::secured_timing;
using security_test::what_of;
namespace topics = detail::topics;
namespace fdds = eprosima::fastdds::dds;

class Security : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { qos::set_intraprocess_delivery(false); }
  static void TearDownTestSuite() { qos::set_intraprocess_delivery(true); }
};

EquipmentOptions secured(int domain, const std::string& uuid, const std::string& identity,
                         qos::Transport transport = qos::Transport::LoopbackUdp) {
  auto o = options(domain, uuid, transport);
  o.timing = secured_timing();
  o.security_dir = Pki::get().dir(identity);
  return o;
}

// A hand-made participant (optionally secured) with one interaction writer
// and one reader in chosen partitions: the adversary of these tests.
class RawParticipant {
 public:
  RawParticipant(int domain, const std::string& security_dir)
      : participant_(domain, qos::participant_qos(config(security_dir))) {
    participant_.register_type(idl::type_support<idl::InteractionSamplePubSubType>());
  }
  static qos::ParticipantConfig config(const std::string& security_dir) {
    qos::ParticipantConfig c;
    c.name = "raw";
    c.transport = qos::Transport::LoopbackUdp;
    c.timing = secured_timing();
    c.security_dir = security_dir;
    return c;
  }
  // The interaction topic of (side, service), made once.
  detail::Topic& topic(SubType side, core::Service service) {
    auto& t = topics_[{side, service}];
    if (!t) {
      t = std::make_unique<detail::Topic>(
          participant_, topics::interaction_topic(side, service), "mtc::idl::InteractionSample",
          qos::fastdds_topic_qos(qos::state_topic(secured_timing())));
    }
    return *t;
  }
  // Throws CreationError when the permissions refuse the writer.
  void make_writer(SubType side, const std::string& partition_uuid,
                   core::Service service = core::Service::MaterialLoad) {
    writer_.reset();
    publisher_ = std::make_unique<detail::Publisher>(
        participant_, std::vector<std::string>{topics::device_partition(partition_uuid)});
    writer_ = std::make_unique<detail::Writer<idl::InteractionSample>>(
        *publisher_, topic(side, service),
        qos::fastdds_writer_qos(qos::state_topic(secured_timing())), listener_);
  }
  // `on_data` is called (from a Fast DDS thread, after the samples are
  // counted) when samples arrive, so a test can wait for them.
  void make_reader(SubType side, const std::string& partition_uuid,
                   std::function<void()> on_data = {}) {
    reader_listener_.on_data = std::move(on_data);
    subscriber_ = std::make_unique<detail::Subscriber>(
        participant_, std::vector<std::string>{topics::device_partition(partition_uuid)});
    reader_ = std::make_unique<detail::Reader>(
        *subscriber_, topic(side, core::Service::MaterialLoad),
        qos::fastdds_reader_qos(qos::state_topic(secured_timing())), &reader_listener_);
  }
  // Writes, as `uuid`, the mh1 item of (service, side) in `state`, on
  // whichever topic the writer has.
  void write_item(const std::string& uuid, core::Service service, SubType side,
                  core::InteractionState state, std::uint32_t seq) {
    idl::InteractionSample s;
    s.device_uuid(uuid);
    s.interface_id("mh1");
    s.data_item_id(topics::interaction_item_id("mh1", service, side));
    s.service(topics::to_idl(service));
    s.sub_type(topics::to_idl(side));
    s.state(topics::to_idl(state));
    s.sequence_number(seq);
    s.source_time_ns(topics::realtime_ns());
    writer_->write(s);
  }
  // Poses as `uuid` with an ACTIVE request for MATERIAL_LOAD on mh1.
  void write_active_request(const std::string& uuid, std::uint32_t seq) {
    write_item(uuid, core::Service::MaterialLoad, SubType::Request, core::InteractionState::Active,
               seq);
  }
  int writer_matches() const {
    fdds::PublicationMatchedStatus st;
    writer_->get().get_publication_matched_status(st);
    return st.total_count;
  }
  int reader_matches() const {
    fdds::SubscriptionMatchedStatus st;
    reader_->get().get_subscription_matched_status(st);
    return st.total_count;
  }
  // Samples received so far (the reader's listener takes them).
  int samples_taken() const { return reader_listener_.taken.load(); }

 private:
  using ReturnCode = eprosima::fastrtps::types::ReturnCode_t;
  struct QuietListener : fdds::DataWriterListener {};
  // Takes and counts the samples itself: taking them on the test's thread
  // under the Recorder's lock, while this callback (under the reader's
  // lock) waits for the Recorder's lock to notify, deadlocked.
  struct DataListener : fdds::DataReaderListener {
    void on_data_available(fdds::DataReader* reader) override {
      idl::InteractionSample s;
      fdds::SampleInfo info;
      while (reader->take_next_sample(&s, &info) == ReturnCode::RETCODE_OK) {
        if (info.valid_data) ++taken;
      }
      if (on_data) on_data();
    }
    std::function<void()> on_data;
    std::atomic<int> taken{0};
  };
  detail::Participant participant_;
  QuietListener listener_;
  DataListener reader_listener_;  // outlives reader_
  std::map<std::pair<SubType, core::Service>, std::unique_ptr<detail::Topic>> topics_;
  std::unique_ptr<detail::Publisher> publisher_;
  std::unique_ptr<detail::Writer<idl::InteractionSample>> writer_;
  std::unique_ptr<detail::Subscriber> subscriber_;
  std::unique_ptr<detail::Reader> reader_;
};

// ------------------------------------------------------------ bad files

TEST_F(Security, MissingDirectoryAndFilesAreNamed) {
  const auto missing = Pki::get().dir("nobody");
  EXPECT_NE(what_of([&] { Equipment e(secured(130, "sec-cnc", "nobody")); }).find(missing),
            std::string::npos);
  const auto dir = Pki::get().copy_of("sec-cnc", "no-key");
  security_test::fs::remove(dir + "/key.pem");
  const auto problem = qos::check_security_dir(dir);
  ASSERT_TRUE(problem.has_value());
  EXPECT_NE(problem->find(dir + "/key.pem"), std::string::npos) << *problem;
  EXPECT_FALSE(qos::check_security_dir(Pki::get().dir("sec-cnc")).has_value());
}

TEST_F(Security, PermissionsSignedByAnotherCaAreRejectedNamingTheFile) {
  const auto dir = Pki::get().copy_of("sec-cnc", "other-ca-permissions");
  security_test::fs::copy_file(Pki::get().other_ca_dir("sec-cnc") + "/permissions.p7s",
                               dir + "/permissions.p7s",
                               security_test::fs::copy_options::overwrite_existing);
  auto o = secured(130, "sec-cnc", "sec-cnc");
  o.security_dir = dir;
  const auto what = what_of([&] { Equipment e(o); });
  EXPECT_NE(what.find(dir + "/permissions.p7s"), std::string::npos) << what;
  EXPECT_NE(what.find("another CA"), std::string::npos) << what;
}

TEST_F(Security, TamperedGovernanceIsRejectedNamingTheFile) {
  const auto dir = Pki::get().copy_of("sec-cnc", "tampered-governance");
  auto text = security_test::read_text(dir + "/governance.p7s");
  // Turn payload encryption off: the signature no longer matches.
  const auto at = text.find("<data_protection_kind>ENCRYPT");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, std::string("<data_protection_kind>ENCRYPT").size(),
               "<data_protection_kind>NONE");
  security_test::write_text(dir + "/governance.p7s", text);
  auto oo = mtc::test::loopback<DomainObserverOptions>();
  oo.domain_id = 130;
  oo.security_dir = dir;
  const auto what = what_of([&] { DomainObserver observer(oo, {}); });
  EXPECT_NE(what.find(dir + "/governance.p7s"), std::string::npos) << what;
}

TEST_F(Security, ExpiredIdentityIsRejectedNamingTheFile) {
  auto o = secured(130, "sec-cnc", "sec-cnc");
  o.security_dir = Pki::get().expired_dir("sec-cnc");
  const auto what = what_of([&] { Equipment e(o); });
  EXPECT_NE(what.find(o.security_dir + "/cert.pem"), std::string::npos) << what;
  EXPECT_NE(what.find("expired"), std::string::npos) << what;
}

// Files that pass the pre-flight check but that Fast DDS refuses (here the
// permissions grant another subject): the error still names the directory.
TEST_F(Security, PermissionsOfAnotherIdentityAreRefusedNamingTheDirectory) {
  const auto dir = Pki::get().copy_of("sec-cnc", "foreign-permissions");
  security_test::fs::copy_file(Pki::get().dir("sec-robot") + "/permissions.p7s",
                               dir + "/permissions.p7s",
                               security_test::fs::copy_options::overwrite_existing);
  auto o = secured(130, "sec-cnc", "sec-cnc");
  o.security_dir = dir;
  Equipment cnc(o);
  cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"sec-robot", "mh1"}});
  const auto what = what_of([&] { cnc.start(); });
  EXPECT_NE(what.find("refused the DDS-Security files in " + dir), std::string::npos) << what;
}

// ------------------------------------------------------------ on the wire

// cnc requests MATERIAL_LOAD from robot, both secured; `cable_cut` (test
// transport) cuts both participants' traffic while true.
struct SecuredPair {
  Recorder cnc_rec;
  Recorder robot_rec;
  Equipment cnc;
  Equipment robot;
  Requester* load = nullptr;
  Responder* respond = nullptr;
  std::atomic<int> requests_seen{0};

  explicit SecuredPair(int domain, qos::Transport transport = qos::Transport::LoopbackUdp,
                       const std::shared_ptr<std::atomic<bool>>& cable_cut = nullptr)
      : cnc(with_outage(secured(domain, "sec-cnc", "sec-cnc", transport), cable_cut),
            cnc_rec.callbacks()),
        robot(with_outage(secured(domain, "sec-robot", "sec-robot", transport), cable_cut),
              robot_rec.callbacks()) {
    cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"sec-robot", "mh1"}});
    robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"sec-cnc", "mh1"}});
    load = &cnc.add_requester("mh1", core::Service::MaterialLoad);
    ResponderCallbacks cb;
    cb.on_request = [this](Responder& r) {
      ++requests_seen;
      r.complete();
    };
    respond = &robot.add_responder("mh1", core::Service::MaterialLoad, cb);
  }
  static EquipmentOptions with_outage(EquipmentOptions o, std::shared_ptr<std::atomic<bool>> cut) {
    o.faults.outage = std::move(cut);
    return o;
  }
  void start_and_pair() {
    cnc.start();
    robot.start();
    ASSERT_TRUE(cnc_rec.wait([&] { return load->counterpart_state() == InteractionState::Ready; }))
        << cnc_rec.dump();
    ASSERT_TRUE(robot_rec.wait([&] {
      return respond->counterpart_state() == InteractionState::Ready;
    })) << robot_rec.dump();
  }
};

TEST_F(Security, HandshakeCompletesSecured) {
  SecuredPair cell(131);
  cell.start_and_pair();
  RequestOptions wait;
  wait.wait_for_ready = 10s;
  auto result = cell.load->request(wait);
  ASSERT_EQ(result.wait_for(kTimeout), std::future_status::ready);
  EXPECT_EQ(result.get().outcome, Outcome::Completed) << cell.cnc_rec.dump();
  EXPECT_TRUE(cell.robot_rec.wait_state(*cell.respond, InteractionState::Ready));
}

TEST_F(Security, CommsLossIsDetectedAndRecoveredSecured) {
  auto cut = std::make_shared<std::atomic<bool>>(false);
  SecuredPair cell(132, qos::Transport::LoopbackTest, cut);
  cell.start_and_pair();
  cut->store(true);
  ASSERT_TRUE(cell.cnc_rec.wait_link(cell.cnc, "mh1", LinkState::Lost)) << cell.cnc_rec.dump();
  EXPECT_TRUE(cell.cnc_rec.wait_state(*cell.load, InteractionState::Fail)) << cell.cnc_rec.dump();
  EXPECT_TRUE(cell.robot_rec.wait_state(*cell.respond, InteractionState::Fail))
      << cell.robot_rec.dump();
  cut->store(false);
  // Both sides back to READY, each seeing the other READY (the recovery
  // waits for the link and the counterpart's acknowledgement).
  ASSERT_TRUE(cell.cnc_rec.wait_state(*cell.load, InteractionState::Ready)) << cell.cnc_rec.dump();
  ASSERT_TRUE(cell.robot_rec.wait_state(*cell.respond, InteractionState::Ready))
      << cell.robot_rec.dump();
  ASSERT_TRUE(
      cell.cnc_rec.wait([&] { return cell.load->counterpart_state() == InteractionState::Ready; }));
  RequestOptions wait;
  wait.wait_for_ready = 10s;
  EXPECT_EQ(cell.load->request(wait).get().outcome, Outcome::Completed) << cell.cnc_rec.dump();
}

// The same adversary, once unauthenticated and once with a valid identity
// allowed to read every partition (the control: it does see the cell).
TEST_F(Security, UnauthenticatedParticipantSeesNothingAndMovesNothing) {
  SecuredPair cell(133);
  cell.start_and_pair();
  // Reading first (a rogue writer would match a rogue reader: both are
  // unauthenticated). The control and the rogue start together; the
  // control matches the cnc's request writer and receives its READY (state
  // topics carry changes only; a late reader gets the last one), then the
  // changes of one handshake. The rogue sees none of it.
  {
    RawParticipant control(133, Pki::get().dir("sec-intruder"));
    control.make_reader(SubType::Request, "sec-cnc", [&] { cell.cnc_rec.notify(); });
    RawParticipant rogue(133, "");
    rogue.make_reader(SubType::Request, "sec-cnc");
    ASSERT_TRUE(cell.cnc_rec.wait([&] { return control.samples_taken() >= 1; }));
    RequestOptions wait;
    wait.wait_for_ready = 10s;
    EXPECT_EQ(cell.load->request(wait).get().outcome, Outcome::Completed) << cell.cnc_rec.dump();
    ASSERT_TRUE(cell.cnc_rec.wait([&] { return control.samples_taken() >= 3; }));
    EXPECT_EQ(rogue.reader_matches(), 0);
    EXPECT_EQ(rogue.samples_taken(), 0);
  }
  // Then writing: posing as the cnc with an ACTIVE request for a few
  // participant announcement periods (500 ms). There is no event to wait
  // for when nothing must happen: the window is the test.
  const int requests_before = cell.requests_seen.load();  // the control's handshake
  RawParticipant rogue_writer(133, "");
  rogue_writer.make_writer(SubType::Request, "sec-cnc");
  for (std::uint32_t seq = 1; seq <= 15; ++seq) {
    rogue_writer.write_active_request("sec-cnc", seq);
    cell.robot_rec.wait([] { return false; }, std::chrono::milliseconds(200));
  }
  EXPECT_EQ(rogue_writer.writer_matches(), 0);
  EXPECT_EQ(cell.requests_seen.load(), requests_before);
  EXPECT_EQ(cell.respond->state(), InteractionState::Ready) << cell.robot_rec.dump();
  EXPECT_EQ(cell.respond->counterpart_state(), InteractionState::Ready) << cell.robot_rec.dump();
}

TEST_F(Security, ValidIdentityCannotWriteWhatItsPermissionsDoNotGrant) {
  const auto intruder = Pki::get().dir("sec-intruder");
  RawParticipant raw(134, intruder);
  // A RESPONSE: the intruder provides no service.
  EXPECT_THROW(raw.make_writer(SubType::Response, "sec-intruder"), CreationError);
  // A REQUEST of the service it requests, in another device's partition,
  // posing as the cnc.
  EXPECT_THROW(raw.make_writer(SubType::Request, "sec-cnc", core::Service::OpenDoor),
               CreationError);
  // The same in its own partition is granted: the refusals above are the
  // permissions.
  EXPECT_NO_THROW(raw.make_writer(SubType::Request, "sec-intruder", core::Service::OpenDoor));

  // An Equipment that claims to be the robot with the intruder's identity
  // cannot start, so the real cnc's requester never pairs nor moves.
  SecuredPair cell(134);
  cell.cnc.start();
  auto o = secured(134, "sec-robot", "sec-intruder");
  Equipment fake_robot(o);
  fake_robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"sec-cnc", "mh1"}});
  ResponderCallbacks cb;
  cb.on_request = [](Responder& r) { r.complete(); };
  fake_robot.add_responder("mh1", core::Service::MaterialLoad, cb);
  EXPECT_THROW(fake_robot.start(), CreationError);
  EXPECT_FALSE(cell.cnc_rec.wait([&] { return cell.cnc.link_state("mh1") == LinkState::Up; },
                                 std::chrono::seconds(3)));
  EXPECT_EQ(cell.load->counterpart_state(), InteractionState::Unavailable);
}

// A device may publish RESPONSE items only of the services it provides
// (issue 11). The robot provides MATERIAL_LOAD only: with its own valid
// identity it cannot make a writer of mtc/InteractionResponse/MATERIAL_UNLOAD,
// not even in its own partition (its permissions grant no such topic), and a
// MATERIAL_UNLOAD item written on the MATERIAL_LOAD topic it may use is a
// protocol violation that the cnc and an observer (the bridge's tap) report
// by name and ignore: the cnc's MATERIAL_UNLOAD requester never moves.
TEST_F(Security, DeviceCannotRespondForAServiceItDoesNotProvide) {
  constexpr int kDomain = 139;
  Recorder cnc_rec;
  Equipment cnc(secured(kDomain, "sec-cnc", "sec-cnc"), cnc_rec.callbacks());
  cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"sec-robot", "mh1"}});
  auto& load = cnc.add_requester("mh1", core::Service::MaterialLoad);
  auto& unload = cnc.add_requester("mh1", core::Service::MaterialUnload);
  cnc.start();
  std::vector<std::string> observer_reports;  // guarded by the recorder's wake-ups
  std::mutex reports_mutex;
  DomainObserverOptions oo;
  oo.domain_id = kDomain;
  oo.transport = qos::Transport::LoopbackUdp;
  oo.timing = secured_timing();
  oo.security_dir = Pki::get().dir("sec-watcher");
  DomainObserverCallbacks ocb;
  ocb.on_protocol_violation = [&](const std::string&, const std::string& report) {
    {
      std::lock_guard<std::mutex> lock(reports_mutex);
      observer_reports.push_back(report);
    }
    cnc_rec.notify();
  };
  DomainObserver observer(oo, ocb);

  RawParticipant robot(kDomain, Pki::get().dir("sec-robot"));
  const auto refused = what_of([&] {
    robot.make_writer(SubType::Response, "sec-robot", core::Service::MaterialUnload);
    // Only reached when the permissions let it through (the red check):
    // the READY then reaches the cnc, whose requester sees it.
    robot.write_item("sec-robot", core::Service::MaterialUnload, SubType::Response,
                     InteractionState::Ready, 1);
    cnc_rec.wait([&] { return unload.counterpart_state() != InteractionState::Unavailable; });
  });
  EXPECT_EQ(unload.counterpart_state(), InteractionState::Unavailable) << cnc_rec.dump();
  EXPECT_NE(refused.find("create_datawriter mtc/InteractionResponse/MATERIAL_UNLOAD"),
            std::string::npos)
      << refused;
  // The control: its MATERIAL_LOAD RESPONSE topic is granted, and its READY
  // reaches the cnc.
  ASSERT_NO_THROW(robot.make_writer(SubType::Response, "sec-robot", core::Service::MaterialLoad));
  robot.write_item("sec-robot", core::Service::MaterialLoad, SubType::Response,
                   InteractionState::Ready, 1);
  ASSERT_TRUE(cnc_rec.wait([&] { return load.counterpart_state() == InteractionState::Ready; }))
      << cnc_rec.dump();
  const auto unload_transitions = [&cnc_rec] {
    const auto all = cnc_rec.transitions();
    return std::count_if(all.begin(), all.end(), [](const TransitionEvent& e) {
      return e.step.service == core::Service::MaterialUnload;
    });
  };
  const auto unload_before = unload.state();
  const auto unload_transitions_before = unload_transitions();

  // The lie: a MATERIAL_UNLOAD RESPONSE item on the MATERIAL_LOAD topic.
  robot.write_item("sec-robot", core::Service::MaterialUnload, SubType::Response,
                   InteractionState::Ready, 2);
  const std::string named =
      "mh1_material_unload_response (MATERIAL_UNLOAD RESPONSE) on topic "
      "mtc/InteractionResponse/MATERIAL_LOAD";
  EXPECT_TRUE(cnc_rec.wait_diagnostic("protocol violation: device sec-robot wrote " + named))
      << cnc_rec.dump();
  EXPECT_TRUE(cnc_rec.wait([&] {
    std::lock_guard<std::mutex> lock(reports_mutex);
    return !observer_reports.empty();
  }));
  {
    std::lock_guard<std::mutex> lock(reports_mutex);
    EXPECT_EQ(observer_reports.size(), 1u);
    for (const auto& report : observer_reports) {
      EXPECT_NE(report.find(named), std::string::npos) << report;
    }
  }
  EXPECT_EQ(unload.counterpart_state(), InteractionState::Unavailable) << cnc_rec.dump();
  EXPECT_EQ(unload.state(), unload_before);
  EXPECT_EQ(unload_transitions(), unload_transitions_before) << cnc_rec.dump();
}

// ------------------------------------------------------------ restarts

// The secured cnc restarted in-process under its uuid and identity, six
// times in quick succession, pairs with the running robot and completes a
// handshake every time. The process first made and deleted 32 participants,
// as a long-lived process that restarts its equipment has: Fast DDS never
// reuses a participant id, and while the discovery port followed the id
// (before qos::anchor_discovery_port), every participant made after that
// listened beyond the 32 ports loopback discovery announces to, so the
// robot and each new cnc never found each other (mtc-bench-security paired
// 5 of 10 secured start-ups and then completed no handshake).
TEST_F(Security, SecuredRequesterRestartedUnderItsUuidPairsAndHandshakesEveryTime) {
  constexpr int kDomain = 138;
  for (int i = 0; i < 32; ++i) {
    detail::Participant aged(kDomain, qos::participant_qos(RawParticipant::config("")));
  }
  Recorder robot_rec;
  Equipment robot(secured(kDomain, "sec-robot", "sec-robot"), robot_rec.callbacks());
  robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"sec-cnc", "mh1"}});
  ResponderCallbacks cb;
  cb.on_request = [](Responder& r) { r.complete(); };
  robot.add_responder("mh1", core::Service::MaterialLoad, cb);
  robot.start();
  constexpr int kRestarts = 6;
  for (int round = 0; round < kRestarts; ++round) {
    SCOPED_TRACE("cnc incarnation " + std::to_string(round));
    Recorder cnc_rec;
    Equipment cnc(secured(kDomain, "sec-cnc", "sec-cnc"), cnc_rec.callbacks());
    cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"sec-robot", "mh1"}});
    auto& load = cnc.add_requester("mh1", core::Service::MaterialLoad);
    cnc.start();
    ASSERT_TRUE(cnc_rec.wait([&] { return load.counterpart_state() == InteractionState::Ready; }))
        << cnc_rec.dump() << "robot:\n"
        << robot_rec.dump();
    RequestOptions wait;
    wait.wait_for_ready = 10s;
    auto result = load.request(wait);
    ASSERT_EQ(result.wait_for(kTimeout), std::future_status::ready) << cnc_rec.dump();
    EXPECT_EQ(result.get().outcome, Outcome::Completed) << cnc_rec.dump() << "robot:\n"
                                                        << robot_rec.dump();
  }
}

}  // namespace
}  // namespace mtc::dds::testing
