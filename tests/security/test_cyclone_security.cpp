// DDS-Security over Cyclone DDS (issue 9, step 10): the same PKI, governance
// and permissions (scripts/security/make-pki.sh) secure equipment on
// Cyclone. Every pair is mixed, one side on Fast DDS and one on Cyclone,
// because two Cyclone participants of one process share a domain instance
// and deliver to each other without the wire: across vendors every sample
// crosses a transport, its authentication and its encryption. Domains
// 164-166 (MTC_CYCLONE builds).
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "../dds/equipment_fixture.hpp"
#include "mtc/dds/domain_observer.hpp"
#include "mtc/dds/error.hpp"
#include "mtc/qos/participant_qos.hpp"
#include "security_pki.hpp"
#include "security_test_helpers.hpp"
#include "transport.hpp"

namespace mtc::dds::testing {
namespace {

using core::InterfaceType;
using security_test::Pki;
using security_test::secured_timing;
using security_test::what_of;
using namespace std::chrono_literals;

EquipmentOptions secured_on(Middleware middleware, int domain, const std::string& identity) {
  auto o = options(domain, identity, qos::Transport::LoopbackUdp);
  o.timing = secured_timing();
  o.middleware = middleware;
  o.security_dir = Pki::get().dir(identity);
  return o;
}

class CycloneSecurity : public ::testing::Test {
 protected:
  // Fast DDS would otherwise hand samples between participants of this
  // process without its transports.
  static void SetUpTestSuite() { qos::set_intraprocess_delivery(false); }
  static void TearDownTestSuite() { qos::set_intraprocess_delivery(true); }
};

// A machine requests MATERIAL_LOAD, a robot responds, both secured, each on
// its own middleware.
struct MixedSecuredPair {
  Recorder cnc_rec;
  Recorder robot_rec;
  Equipment cnc;
  Equipment robot;
  Requester* load = nullptr;
  Responder* respond = nullptr;

  MixedSecuredPair(int domain, Middleware cnc_on, Middleware robot_on)
      : cnc(secured_on(cnc_on, domain, "sec-cnc"), cnc_rec.callbacks()),
        robot(secured_on(robot_on, domain, "sec-robot"), robot_rec.callbacks()) {
    cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"sec-robot", "mh1"}});
    robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"sec-cnc", "mh1"}});
    load = &cnc.add_requester("mh1", core::Service::MaterialLoad);
    ResponderCallbacks cb;
    cb.on_request = [](Responder& r) { r.complete(); };
    respond = &robot.add_responder("mh1", core::Service::MaterialLoad, cb);
  }
  void start_and_pair() {
    cnc.start();
    robot.start();
    ASSERT_TRUE(cnc_rec.wait([&] { return load->counterpart_state() == InteractionState::Ready; }))
        << cnc_rec.dump() << robot_rec.dump();
    ASSERT_TRUE(robot_rec.wait([&] {
      return respond->counterpart_state() == InteractionState::Ready;
    })) << robot_rec.dump();
  }
  void handshake() {
    RequestOptions wait;
    wait.wait_for_ready = 10s;
    auto result = load->request(wait);
    ASSERT_EQ(result.wait_for(20s), std::future_status::ready);
    EXPECT_EQ(result.get().outcome, Outcome::Completed) << cnc_rec.dump() << robot_rec.dump();
    EXPECT_TRUE(robot_rec.wait_state(*respond, InteractionState::Ready)) << robot_rec.dump();
  }
};

// Which side begins the authentication handshake is fixed for a pair of
// identities: their GUIDs start with a hash of the certificate subject, and
// the greater begins. For sec-cnc and sec-robot, sec-robot begins.
//
// The robot on Cyclone begins with ECDH (prime256v1), which Fast DDS 2.9.1
// answers: the pair authenticates and handshakes.
// make-pki.sh writes that order down (first begins); the two cases below
// hold only if it is right.
std::vector<std::string> authentication_order() {
  std::istringstream lines(
      security_test::read_text(Pki::get().root() / "a" / "authentication-order.txt"));
  std::vector<std::string> order;
  for (std::string name; std::getline(lines, name);) order.push_back(name);
  return order;
}

bool begins_before(const std::string& first, const std::string& second) {
  const auto order = authentication_order();
  const auto a = std::find(order.begin(), order.end(), first);
  return a != order.end() && std::find(a, order.end(), second) != order.end();
}

TEST_F(CycloneSecurity, SecuredHandshakeCompletesWhenCycloneBeginsTheAuthentication) {
  ASSERT_TRUE(begins_before("sec-robot", "sec-cnc"));
  MixedSecuredPair cell(164, Middleware::FastDds, Middleware::Cyclone);
  cell.start_and_pair();
  cell.handshake();
}

// The robot on Fast DDS 2.9.1 begins with DH (MODP-2048, its only choice:
// no preferred_key_agreement before 2.10) and sends its public key as raw
// bytes; Cyclone 0.10.2 reads it as an ASN.1 INTEGER and refuses ("Begin
// handshake reply failed: Failed to convert octet sequence to ASN1
// integer", eclipse-cyclonedds/cyclonedds#701), every second, for good. The
// pair never meets. Pinned here, so that a Debian upgrade that fixes either
// side turns this red and docs/security.md is updated; there is no event
// for "never", so a window of five of Cyclone's retries is the test.
TEST_F(CycloneSecurity, SecuredPairNeverMeetsWhenFastDdsBeginsTheAuthentication) {
  ASSERT_TRUE(begins_before("sec-robot", "sec-cnc"));
  MixedSecuredPair cell(165, Middleware::Cyclone, Middleware::FastDds);
  cell.cnc.start();
  cell.robot.start();
  EXPECT_FALSE(cell.cnc_rec.wait(
      [&] { return cell.load->counterpart_state() != InteractionState::Unavailable; }, 5s))
      << cell.cnc_rec.dump();
  EXPECT_EQ(cell.respond->counterpart_state(), InteractionState::Unavailable)
      << cell.robot_rec.dump();
}

// The secured Cyclone robot's announcement reaches an observer the
// permissions name (sec-watcher) and not one without an identity, both on
// Fast DDS, so both read it off the wire. The control is the event to wait
// for: once it has seen both devices and a handshake, the rogue has had the
// same chances.
TEST_F(CycloneSecurity, AnUnauthenticatedObserverSeesNothingOfASecuredCycloneRobot) {
  constexpr int kDomain = 166;
  MixedSecuredPair cell(kDomain, Middleware::FastDds, Middleware::Cyclone);
  std::mutex seen_mutex;
  std::set<std::string> control_saw;
  std::set<std::string> rogue_saw;
  const auto observer = [&](const std::string& identity, std::set<std::string>& saw) {
    auto oo = mtc::test::loopback<DomainObserverOptions>();
    oo.domain_id = kDomain;
    oo.transport = qos::Transport::LoopbackUdp;
    oo.middleware = Middleware::FastDds;
    oo.timing = secured_timing();
    if (!identity.empty()) oo.security_dir = Pki::get().dir(identity);
    DomainObserverCallbacks cb;
    cb.on_device = [&](const ObservedDevice& d) {
      {
        const std::lock_guard<std::mutex> lock(seen_mutex);
        saw.insert(d.device_uuid);
      }
      cell.cnc_rec.notify();
    };
    return std::make_unique<DomainObserver>(oo, cb);
  };
  const auto control = observer("sec-watcher", control_saw);
  const auto rogue = observer("", rogue_saw);
  cell.start_and_pair();
  cell.handshake();
  ASSERT_TRUE(cell.cnc_rec.wait([&] {
    const std::lock_guard<std::mutex> lock(seen_mutex);
    return control_saw.count("sec-robot") == 1 && control_saw.count("sec-cnc") == 1;
  })) << cell.cnc_rec.dump();
  const std::lock_guard<std::mutex> lock(seen_mutex);
  EXPECT_TRUE(rogue_saw.empty()) << "the rogue saw " << *rogue_saw.begin();
}

// What the pre-flight check refuses is named by file before Cyclone sees it;
// what Cyclone refuses itself (permissions granted to another subject) is
// named by directory, as with Fast DDS.
TEST_F(CycloneSecurity, BadFilesAreRefusedNamingThem) {
  const auto tampered = Pki::get().copy_of("sec-robot", "cyclone-tampered-governance");
  auto text = security_test::read_text(tampered + "/governance.p7s");
  const auto at = text.find("<data_protection_kind>ENCRYPT");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, std::string("<data_protection_kind>ENCRYPT").size(),
               "<data_protection_kind>NONE");
  security_test::write_text(tampered + "/governance.p7s", text);
  auto o = secured_on(Middleware::Cyclone, 164, "sec-robot");
  o.security_dir = tampered;
  auto what = what_of([&] { Equipment(o).start(); });
  EXPECT_NE(what.find(tampered + "/governance.p7s"), std::string::npos) << what;

  const auto foreign = Pki::get().copy_of("sec-robot", "cyclone-foreign-permissions");
  security_test::fs::copy_file(Pki::get().dir("sec-cnc") + "/permissions.p7s",
                               foreign + "/permissions.p7s",
                               security_test::fs::copy_options::overwrite_existing);
  o.security_dir = foreign;
  what = what_of([&] {
    Equipment robot(o);
    robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"sec-cnc", "mh1"}});
    robot.start();
  });
  EXPECT_NE(what.find("Cyclone DDS refused the DDS-Security files in " + foreign),
            std::string::npos)
      << what;
}

}  // namespace
}  // namespace mtc::dds::testing
