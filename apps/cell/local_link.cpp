#include "local_link.hpp"

#include <array>
#include <condition_variable>
#include <mutex>
#include <vector>

#include "mtc/core/preconditions.hpp"
#include "mtc/core/requester.hpp"
#include "mtc/core/responder.hpp"

namespace mtc::cell {

using core::InteractionState;
using core::Service;

namespace {

constexpr Millis kTickSlice{20};  // how often waits fire the machines' time limits

std::size_t index_of(Service s) {
  return static_cast<std::size_t>(s);
}

}  // namespace

// Both sides of one service plus what the ports need to know about them.
struct Wire {
  // The hook holds responders NOT_READY while their door/chuck service has
  // nothing to do, as the DDS runtime does (Equipment::set_door_state).
  Wire(Service s, const core::MachineOptions& o, const core::ServicePreconditions& hook)
      : req(s, o), resp(s, o, &hook) {}
  core::Requester req;
  core::Responder resp;
  InteractionState req_seen_by_resp = InteractionState::Unavailable;
  InteractionState resp_seen_by_req = InteractionState::Unavailable;
  bool job_pending = false;  // request went ACTIVE, station not told yet
  bool completed = false;    // requester saw COMPLETE for the current request
};

struct LocalBus::Impl {
  std::mutex mutex;
  std::condition_variable cv;
  // The machine's door and chuck as its responders see them; CLOSED at
  // start like the DDS cell's machine (equipment_link.cpp, layout_of).
  core::DoorChuckPreconditions hook{core::DoorState::Closed, core::ChuckState::Closed};
  std::vector<std::unique_ptr<Wire>> wires;
  std::vector<std::unique_ptr<RequestPort>> request_ports;
  std::vector<std::unique_ptr<ResponsePort>> response_ports;
  std::optional<core::DoorState> door;
  std::optional<core::ChuckState> chuck;

  static void note(Wire& w, const core::StepResult& r) {
    if (r.role == core::Role::Responder && r.notice == core::Notice::RequestObserved) {
      w.job_pending = true;
    }
    if (r.role == core::Role::Requester && r.notice == core::Notice::Completed) {
      w.completed = true;
    }
  }

  // Shows each side the other's current value until neither changes.
  static void propagate(Wire& w, core::TimePoint now) {
    for (int round = 0; round < 16; ++round) {
      bool changed = false;
      if (w.req.state() != w.req_seen_by_resp) {
        w.req_seen_by_resp = w.req.state();
        note(w, w.resp.on_counterpart(w.req_seen_by_resp, now));
        changed = true;
      }
      if (w.resp.state() != w.resp_seen_by_req) {
        w.resp_seen_by_req = w.resp.state();
        note(w, w.req.on_counterpart(w.resp_seen_by_req, now));
        changed = true;
      }
      if (!changed) {
        break;
      }
    }
  }

  void tick(core::TimePoint now) {
    for (auto& w : wires) {
      for (core::ServiceMachine* m : {static_cast<core::ServiceMachine*>(&w->req),
                                      static_cast<core::ServiceMachine*>(&w->resp)}) {
        while (m->next_deadline() <= now) {
          note(*w, m->on_tick(now));
        }
      }
      propagate(*w, now);
    }
  }

  // A door or chuck moved: responders may go NOT_READY or back to READY.
  void reevaluate_all() {
    const auto now = core::Clock::now();
    for (auto& w : wires) {
      note(*w, w->resp.reevaluate(now));
      propagate(*w, now);
    }
  }

  template <class Fn>
  core::StepResult command(Wire& w, Fn fn) {
    core::StepResult r;
    {
      std::lock_guard<std::mutex> lock(mutex);
      const auto now = core::Clock::now();
      r = fn(now);
      note(w, r);
      propagate(w, now);
    }
    cv.notify_all();
    return r;
  }

  // Waits until pred() holds (under the lock), firing time limits meanwhile.
  template <class Pred>
  bool wait(Millis timeout, Pred pred) {
    std::unique_lock<std::mutex> lock(mutex);
    const auto deadline = core::Clock::now() + timeout;
    while (!pred()) {
      const auto now = core::Clock::now();
      if (now >= deadline) {
        return false;
      }
      cv.wait_for(lock, std::min<core::Duration>(kTickSlice, deadline - now));
      tick(core::Clock::now());
    }
    return true;
  }
};

namespace {

class LocalRequestPort : public RequestPort {
 public:
  LocalRequestPort(LocalBus::Impl& bus, Wire& w) : bus_(bus), w_(w) {}

  bool raise(Millis timeout) override {
    if (!bus_.wait(timeout, [&] {
          return w_.req.state() == InteractionState::Ready &&
                 w_.resp.state() == InteractionState::Ready;
        })) {
      return false;
    }
    const auto r = bus_.command(w_, [&](core::TimePoint now) {
      w_.completed = false;
      return w_.req.request(now);
    });
    return !r.rejected();
  }

  bool wait_engaged(Millis timeout) override {
    bool engaged = false;
    bus_.wait(timeout, [&] {
      const auto rs = w_.resp.state();
      engaged = rs == InteractionState::Active || rs == InteractionState::Complete;
      return engaged || w_.req.state() != InteractionState::Active;
    });
    return engaged;
  }

  Outcome wait_outcome(Millis timeout) override {
    Outcome out = Outcome::TimedOut;
    bus_.wait(timeout, [&] {
      if (w_.req.state() == InteractionState::Fail) {
        out = Outcome::Failed;
        return true;
      }
      // Step 8: the responder is back to READY (or NOT_READY) after the ack.
      const auto rs = w_.resp.state();
      if (w_.completed && w_.req.state() == InteractionState::Ready &&
          (rs == InteractionState::Ready || rs == InteractionState::NotReady)) {
        out = Outcome::Completed;
        return true;
      }
      return false;
    });
    return out;
  }

  bool fail() override {
    return !bus_.command(w_, [&](core::TimePoint now) { return w_.req.fail(now); }).rejected();
  }

  std::string states() override {
    std::lock_guard<std::mutex> lock(bus_.mutex);
    return "request " + std::string(core::to_string(w_.req.state())) + ", response " +
           std::string(core::to_string(w_.resp.state()));
  }

  bool recover(Millis timeout) override {
    bus_.wait(timeout, [&] {
      return w_.req.state() != InteractionState::Fail || w_.req.fail_acknowledged();
    });
    bus_.command(w_,
                 [&](core::TimePoint now) { return w_.req.recover(InteractionState::Ready, now); });
    return bus_.wait(Millis(0), [&] { return w_.req.state() == InteractionState::Ready; });
  }

 private:
  LocalBus::Impl& bus_;
  Wire& w_;
};

class LocalResponsePort : public ResponsePort {
 public:
  LocalResponsePort(LocalBus::Impl& bus, Wire& w) : bus_(bus), w_(w) {}

  bool accept() override {
    return !bus_.command(w_, [&](core::TimePoint now) { return w_.resp.accept(now); }).rejected();
  }
  bool complete() override {
    return !bus_.command(w_, [&](core::TimePoint now) { return w_.resp.complete(now); }).rejected();
  }
  void fail() override {
    bus_.command(w_, [&](core::TimePoint now) { return w_.resp.fail(now); });
  }
  Outcome wait_settled(Millis timeout) override {
    Outcome out = Outcome::TimedOut;
    bus_.wait(timeout, [&] {
      const auto s = w_.resp.state();
      if (s == InteractionState::Complete) {
        return false;
      }
      out = s == InteractionState::Fail ? Outcome::Failed : Outcome::Completed;
      return true;
    });
    return out;
  }
  bool failed() override {
    return bus_.wait(Millis(0), [&] { return w_.resp.state() == InteractionState::Fail; });
  }
  InteractionState state() override {
    std::lock_guard<std::mutex> lock(bus_.mutex);
    return w_.resp.state();
  }
  bool cancelled() override {
    return bus_.wait(Millis(0), [&] { return w_.resp.state() != InteractionState::Active; });
  }
  bool recover(Millis timeout) override {
    bus_.wait(timeout, [&] {
      return w_.resp.state() != InteractionState::Fail || w_.resp.fail_acknowledged();
    });
    bus_.command(
        w_, [&](core::TimePoint now) { return w_.resp.recover(InteractionState::Ready, now); });
    // NOT_READY counts: the door/chuck may forbid the service (Table 6).
    return bus_.wait(timeout, [&] {
      const auto s = w_.resp.state();
      return s == InteractionState::Ready || s == InteractionState::NotReady;
    });
  }

 private:
  LocalBus::Impl& bus_;
  Wire& w_;
};

}  // namespace

LocalBus::LocalBus(const core::MachineOptions& options) : impl_(std::make_unique<Impl>()) {
  for (Service s : core::kAllServices) {
    impl_->wires.push_back(std::make_unique<Wire>(s, options, impl_->hook));
    Wire& w = *impl_->wires.back();
    impl_->request_ports.push_back(std::make_unique<LocalRequestPort>(*impl_, w));
    impl_->response_ports.push_back(std::make_unique<LocalResponsePort>(*impl_, w));
    impl_->propagate(w, core::Clock::now());  // both sides see each other READY
  }
}

LocalBus::~LocalBus() = default;

RequestPort& LocalBus::requester(Service s) {
  return *impl_->request_ports.at(index_of(s));
}
ResponsePort& LocalBus::responder(Service s) {
  return *impl_->response_ports.at(index_of(s));
}

std::optional<Service> LocalBus::wait_job(std::initializer_list<Service> services, Millis timeout) {
  std::optional<Service> job;
  impl_->wait(timeout, [&] {
    for (Service s : services) {
      Wire& w = *impl_->wires.at(index_of(s));
      if (w.job_pending) {
        w.job_pending = false;
        job = s;
        return true;
      }
    }
    return false;
  });
  return job;
}

void LocalBus::set_door(core::DoorState state) {
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->door = state;
    impl_->hook.set_door_state(state);
    impl_->reevaluate_all();
  }
  impl_->cv.notify_all();
}

void LocalBus::set_chuck(core::ChuckState state) {
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->chuck = state;
    impl_->hook.set_chuck_state(state);
    impl_->reevaluate_all();
  }
  impl_->cv.notify_all();
}

bool LocalBus::holds(Service s) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return door_chuck_holds(s, impl_->door, impl_->chuck);
}

}  // namespace mtc::cell
