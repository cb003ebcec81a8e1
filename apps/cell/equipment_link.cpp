// The cell's Link over mtc::dds::Equipment. Runtime callbacks (executor
// thread) only record what happened and wake the station threads; the
// stations block on futures and on this link's condition variable, never
// inside a callback.
#include "equipment_link.hpp"

#include <condition_variable>
#include <cstdint>
#include <future>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>

#include "console.hpp"
#include "mtc/dds/equipment.hpp"

namespace mtc::cell {
namespace {

using core::InteractionState;
using core::InterfaceType;
using core::Service;

// Device uuids of the cell; the bridge shows them as devices "machine",
// "robot" and "feeder" (names) built from their DDS announcements.
const char* uuid_of(StationId id) {
  switch (id) {
    case StationId::Machine:
      return "cell-machine";
    case StationId::Robot:
      return "cell-robot";
    case StationId::Feeder:
      return "cell-feeder";
  }
  return "";
}

// Which interface of the cell carries a service.
const char* interface_of(Service s) {
  switch (s) {
    case Service::MaterialFeed:
      return "bar_feeder";
    case Service::OpenDoor:
    case Service::CloseDoor:
      return "door";
    case Service::OpenChuck:
    case Service::CloseChuck:
      return "chuck";
    default:
      return "material_handler";
  }
}

bool is_idle(InteractionState s) {
  return s == InteractionState::Ready || s == InteractionState::NotReady;
}

// State shared by the callbacks and the ports of one equipment.
struct Shared {
  std::mutex mutex;
  std::condition_variable cv;
  std::set<Service> pending_jobs;
  std::set<Service> aborted;
  std::optional<core::DoorState> door;  // as published by the machine
  std::optional<core::ChuckState> chuck;
  std::uint64_t events = 0;  // bumped by touch(): any runtime event

  void touch() {
    {
      std::lock_guard<std::mutex> lock(mutex);
      ++events;
    }
    cv.notify_all();
  }
  std::uint64_t events_seen() {
    std::lock_guard<std::mutex> lock(mutex);
    return events;
  }
  template <class Pred>
  bool wait(Millis timeout, Pred pred) {
    std::unique_lock<std::mutex> lock(mutex);
    return cv.wait_for(lock, timeout, pred);
  }
};

// FAIL -> READY through the runtime: refused until the counterpart has
// acknowledged our FAIL, so retry on each runtime event until then. The
// acknowledgement changes the counterpart's state (or is the fail_ack
// waiver), not ours: waiting for our own state to change slept through it
// until the caller's next slice. With the AfterCommsLoss policy the
// runtime may already have cleared it.
bool recover_handle(dds::ServiceHandle& h, Shared& shared, Millis timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    const auto seen = shared.events_seen();  // before recover(): no event is lost
    // NOT_READY counts: a responder whose door/chuck precondition forbids
    // the service recovers to NOT_READY (Table 6), which is idle and sound.
    const auto state = h.state();
    if (is_idle(state)) {
      return true;
    }
    if (state == InteractionState::Fail) {
      h.recover().get();
      if (is_idle(h.state())) {
        return true;
      }
    }
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) {
      return false;
    }
    shared.wait(std::chrono::duration_cast<Millis>(deadline - now),
                [&] { return shared.events != seen; });
  }
}

class DdsRequestPort : public RequestPort {
 public:
  DdsRequestPort(dds::Requester& r, Shared& shared) : r_(r), shared_(shared) {}

  bool raise(Millis timeout) override {
    // A FAIL left from a loss while idle is cleared first (nothing to reset).
    if (r_.state() == InteractionState::Fail && !recover_handle(r_, shared_, timeout)) {
      return false;
    }
    result_.reset();
    pending_ = r_.request(dds::RequestOptions{timeout});
    // Issued once the request is ACTIVE; a refusal resolves the future.
    shared_.wait(timeout + Millis(500), [&] {
      return r_.state() == InteractionState::Active ||
             pending_.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
    });
    if (pending_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
      result_ = pending_.get();
      return result_->outcome != dds::Outcome::Rejected;
    }
    return r_.state() == InteractionState::Active;
  }

  bool wait_engaged(Millis timeout) override {
    auto engaged = [&] {
      const auto c = r_.counterpart_state();
      return c == InteractionState::Active || c == InteractionState::Complete;
    };
    shared_.wait(timeout, [&] { return engaged() || r_.state() != InteractionState::Active; });
    return engaged();
  }

  Outcome wait_outcome(Millis timeout) override {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    if (!result_ && pending_.valid()) {
      if (pending_.wait_for(timeout) != std::future_status::ready) {
        return Outcome::TimedOut;
      }
      result_ = pending_.get();
    }
    if (!result_) {
      return Outcome::Failed;
    }
    if (result_->outcome != dds::Outcome::Completed) {
      return Outcome::Failed;
    }
    // Steps 7-8: the responder returns to READY (NOT_READY when, say, the
    // door it just opened now forbids another OPEN_DOOR).
    const auto left =
        std::chrono::duration_cast<Millis>(deadline - std::chrono::steady_clock::now());
    const bool idle =
        shared_.wait(std::max(left, Millis(0)), [&] { return is_idle(r_.counterpart_state()); });
    return idle ? Outcome::Completed : Outcome::TimedOut;
  }

  bool fail() override { return !r_.fail().get().rejected(); }

  bool recover(Millis timeout) override { return recover_handle(r_, shared_, timeout); }

  std::string states() override {
    return "request " + std::string(core::to_string(r_.state())) + ", response " +
           std::string(core::to_string(r_.counterpart_state()));
  }

  std::string why_failed() override {
    if (!result_ || result_->outcome == dds::Outcome::Completed) return {};
    return std::string(dds::to_string(result_->outcome)) + ": " +
           std::string(core::describe(result_->reason));
  }

 private:
  dds::Requester& r_;
  Shared& shared_;
  std::future<dds::RequestResult> pending_;
  std::optional<dds::RequestResult> result_;
};

class DdsResponsePort : public ResponsePort {
 public:
  DdsResponsePort(dds::Responder& r, Shared& shared, Service s)
      : r_(r), shared_(shared), service_(s) {}

  bool accept() override {
    {
      std::lock_guard<std::mutex> lock(shared_.mutex);
      shared_.aborted.erase(service_);
    }
    return !r_.accept().get().rejected();
  }
  bool complete() override { return !r_.complete().get().rejected(); }
  void fail() override { r_.fail().get(); }
  bool cancelled() override {
    std::lock_guard<std::mutex> lock(shared_.mutex);
    return shared_.aborted.count(service_) > 0 || r_.state() != InteractionState::Active;
  }
  bool recover(Millis timeout) override { return recover_handle(r_, shared_, timeout); }
  Outcome wait_settled(Millis timeout) override {
    const bool ended =
        shared_.wait(timeout, [&] { return r_.state() != InteractionState::Complete; });
    if (!ended) {
      return Outcome::TimedOut;
    }
    return is_idle(r_.state()) ? Outcome::Completed : Outcome::Failed;
  }
  bool failed() override { return r_.state() == InteractionState::Fail; }
  InteractionState state() override { return r_.state(); }

 private:
  dds::Responder& r_;
  Shared& shared_;
  Service service_;
};

struct Layout {
  std::vector<dds::InterfaceConfig> interfaces;
  std::vector<Service> requests;
  std::vector<Service> responses;
};

dds::InterfaceConfig interface(const char* id, InterfaceType type, StationId peer) {
  dds::InterfaceConfig c;
  c.id = id;
  c.type = type;
  c.counterpart = {uuid_of(peer), id};
  return c;
}

Layout layout_of(StationId id) {
  Layout l;
  switch (id) {
    case StationId::Machine: {
      l.interfaces.push_back(
          interface("material_handler", InterfaceType::MaterialHandler, StationId::Robot));
      auto door = interface("door", InterfaceType::Door, StationId::Robot);
      door.publishes_door_state = true;
      door.initial_door_state = core::DoorState::Closed;
      auto chuck = interface("chuck", InterfaceType::Chuck, StationId::Robot);
      chuck.publishes_chuck_state = true;
      chuck.initial_chuck_state = core::ChuckState::Closed;
      l.interfaces.push_back(door);
      l.interfaces.push_back(chuck);
      l.interfaces.push_back(interface("bar_feeder", InterfaceType::BarFeeder, StationId::Feeder));
      l.requests = {Service::MaterialFeed, Service::MaterialLoad, Service::MaterialUnload};
      l.responses = {Service::OpenDoor, Service::CloseDoor, Service::OpenChuck,
                     Service::CloseChuck};
      break;
    }
    case StationId::Robot:
      l.interfaces.push_back(
          interface("material_handler", InterfaceType::MaterialHandler, StationId::Machine));
      l.interfaces.push_back(interface("door", InterfaceType::Door, StationId::Machine));
      l.interfaces.push_back(interface("chuck", InterfaceType::Chuck, StationId::Machine));
      l.requests = {Service::OpenDoor, Service::CloseDoor, Service::OpenChuck, Service::CloseChuck};
      l.responses = {Service::MaterialLoad, Service::MaterialUnload};
      break;
    case StationId::Feeder:
      l.interfaces.push_back(interface("bar_feeder", InterfaceType::BarFeeder, StationId::Machine));
      l.responses = {Service::MaterialFeed};
      break;
  }
  return l;
}

class EquipmentLink : public Link {
 public:
  EquipmentLink(StationId id, const CellOptions& options) : id_(id) {
    dds::EquipmentOptions eo;
    eo.domain_id = options.domain_id;
    eo.device_uuid = uuid_of(id);
    eo.device_name = std::string(to_string(id));
    eo.timing = options.timing;
    eo.transport = options.transport;
    eo.middleware = middleware_of(id, options);
    eo.security_dir = security_dir_of(id, options);
    equipment_ = std::make_unique<dds::Equipment>(eo, callbacks());
    const Layout l = layout_of(id);
    for (const auto& i : l.interfaces) {
      equipment_->add_interface(i);
    }
    dds::ServiceOptions so;
    so.auto_accept = false;  // the stations accept (or fail at once: scenario 1)
    // A FAIL the counterpart never acknowledges (it had already recovered,
    // or it was lost meanwhile) may be cleared after 2 s instead of pinning
    // this side in FAIL for good (core::TimeLimits::fail_ack).
    so.limits.fail_ack = std::chrono::seconds(2);
    for (Service s : l.requests) {
      auto& r = equipment_->add_requester(interface_of(s), s, so);
      requests_.emplace(s, std::make_unique<DdsRequestPort>(r, shared_));
    }
    for (Service s : l.responses) {
      dds::ResponderCallbacks rc;
      rc.on_request = [this, s](dds::Responder&) {
        {
          std::lock_guard<std::mutex> lock(shared_.mutex);
          shared_.pending_jobs.insert(s);
        }
        shared_.cv.notify_all();
      };
      rc.on_abort = [this, s](dds::Responder&, core::Reason) {
        {
          std::lock_guard<std::mutex> lock(shared_.mutex);
          shared_.aborted.insert(s);
        }
        shared_.cv.notify_all();
      };
      auto& r = equipment_->add_responder(interface_of(s), s, rc, so);
      responses_.emplace(s, std::make_unique<DdsResponsePort>(r, shared_, s));
    }
    equipment_->start();
    // Which middleware this station's equipment runs on, as its participant
    // says once started (cell.mixed_middleware_bounded_run reads it).
    print_line(to_string(id_),
               "DDS middleware " + std::string(dds::to_string(equipment_->middleware())));
  }

  RequestPort& requester(Service s) override { return *requests_.at(s); }
  ResponsePort& responder(Service s) override { return *responses_.at(s); }

  std::optional<Service> wait_job(std::initializer_list<Service> services,
                                  Millis timeout) override {
    std::optional<Service> job;
    shared_.wait(timeout, [&] {
      for (Service s : services) {
        if (shared_.pending_jobs.erase(s) > 0) {
          job = s;
          return true;
        }
      }
      return false;
    });
    return job;
  }

  void set_door(core::DoorState state) override { equipment_->set_door_state("door", state).get(); }
  void set_chuck(core::ChuckState state) override {
    equipment_->set_chuck_state("chuck", state).get();
  }
  bool holds(Service s) override {
    std::lock_guard<std::mutex> lock(shared_.mutex);
    return door_chuck_holds(s, shared_.door, shared_.chuck);
  }

 private:
  dds::EquipmentCallbacks callbacks() {
    dds::EquipmentCallbacks cb;
    cb.on_transition = [this](const dds::TransitionEvent&) { shared_.touch(); };
    cb.on_link = [this](const dds::LinkEvent& e) {
      if (e.current == dds::LinkState::Lost || e.previous == dds::LinkState::Lost) {
        print_line(
            to_string(id_),
            format("link %s -> %s: %s (%s)", e.interface_id.c_str(), e.counterpart_uuid.c_str(),
                   std::string(dds::to_string(e.current)).c_str(), e.cause.c_str()));
      }
      shared_.touch();
    };
    cb.on_counterpart_value = [this](const dds::ObservedValue& v) { note_value(v); };
    cb.on_diagnostic = [this](const std::string& text) {
      // "ignored ... after only N ms of silence": the runtime filtering a
      // false loss alarm; the cell's log is about the cell, so leave it out.
      if (text.rfind("ignored", 0) == 0) {
        return;
      }
      print_line(to_string(id_), "runtime: " + text);
    };
    return cb;
  }

  void note_value(const dds::ObservedValue& v) {
    if (v.kind() == dds::ItemKind::Interaction) {
      shared_.touch();  // a change (or the last value after a loss): waits re-check
      return;
    }
    if (v.kind() != dds::ItemKind::DoorState && v.kind() != dds::ItemKind::ChuckState) {
      return;
    }
    {
      std::lock_guard<std::mutex> lock(shared_.mutex);
      if (v.kind() == dds::ItemKind::DoorState) {
        shared_.door = v.state.door();
      } else {
        shared_.chuck = v.state.chuck();
      }
    }
    shared_.cv.notify_all();
  }

  StationId id_;
  Shared shared_;
  std::map<Service, std::unique_ptr<DdsRequestPort>> requests_;
  std::map<Service, std::unique_ptr<DdsResponsePort>> responses_;
  // Last member: destroyed first, so no callback outlives the ports.
  std::unique_ptr<dds::Equipment> equipment_;
};

}  // namespace

std::string security_dir_of(StationId id, const CellOptions& options) {
  if (options.security_dir.empty()) return "";
  return options.security_dir + "/" + uuid_of(id);
}

std::unique_ptr<Link> make_equipment_link(StationId id, const CellOptions& options) {
  try {
    return std::make_unique<EquipmentLink>(id, options);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("equipment ") + uuid_of(id) + ": " + e.what());
  }
}

}  // namespace mtc::cell
