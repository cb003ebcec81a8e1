#include "pairs.hpp"

#include <unistd.h>

#include <iostream>
#include <memory>
#include <mutex>
#include <thread>

#include "mtc/bench/peer_process.hpp"

namespace mtc::bench::scale {
namespace {

using namespace std::chrono_literals;

Stepping g_stepping = Stepping::Default;  // set once by main, before any thread
mtc::dds::Middleware g_middleware = mtc::dds::Middleware::FastDds;  // likewise

// Completes every request at once. The runtime may hand a request to
// on_request before start() has returned (the executor runs while start()
// still creates entities; a command then throws "call start() first"):
// such requests are completed once start() is back.
class Completer {
 public:
  mtc::dds::ResponderCallbacks callbacks() {
    mtc::dds::ResponderCallbacks cb;
    cb.on_request = [this](mtc::dds::Responder& r) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!started_) {
          pending_.push_back(&r);
          return;
        }
      }
      r.complete(nullptr);  // no future: settling one costs a system call
    };
    return cb;
  }

  void started() {
    std::vector<mtc::dds::Responder*> pending;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      started_ = true;
      pending.swap(pending_);
    }
    for (auto* r : pending) {
      r->complete(nullptr);
    }
  }

 private:
  std::mutex mutex_;
  bool started_ = false;
  std::vector<mtc::dds::Responder*> pending_;
};

}  // namespace

std::string device(const char* role, int index) {
  return std::string("scale-") + role + "-" + std::to_string(index);
}

std::string interface_id(int index) {
  return "if" + std::to_string(index);
}

mtc::dds::EquipmentOptions equipment_options(const std::string& uuid, int domain) {
  mtc::dds::EquipmentOptions o;
  o.domain_id = domain;
  o.device_uuid = uuid;
  o.middleware = g_middleware;
  o.transport = g_middleware == mtc::dds::Middleware::Cyclone ? mtc::qos::Transport::LoopbackUdp
                                                              : mtc::qos::Transport::Loopback;
  o.recovery = mtc::dds::RecoveryPolicy::Always;  // a false alarm must not stall a pair
  apply(g_stepping, o);
  return o;
}

void set_stepping(Stepping stepping) {
  g_stepping = stepping;
}

Stepping stepping() {
  return g_stepping;
}

void set_middleware(mtc::dds::Middleware m) {
  g_middleware = m;
}

const char* transport_name() {
  return g_middleware == mtc::dds::Middleware::Cyclone ? "udp_loopback" : "shm_udp";
}

mtc::dds::EquipmentCallbacks quiet_callbacks() {
  mtc::dds::EquipmentCallbacks cb;
  cb.on_diagnostic = [](const std::string& text) {
    if (text.rfind("ignored", 0) != 0) {
      std::cerr << "runtime: " << text << "\n";
    }
  };
  return cb;
}

void add_pairing(mtc::dds::Equipment& e, const std::string& peer_device, int interfaces) {
  for (int k = 0; k < interfaces; ++k) {
    mtc::dds::InterfaceConfig c;
    c.id = interface_id(k);
    c.type = mtc::core::InterfaceType::MaterialHandler;
    c.counterpart = {peer_device, c.id};
    e.add_interface(c);
  }
}

int run_peer(int devices, int interfaces, int domain) {
  const sigset_t stop_signals = block_stop_signals();  // before the runtime starts threads
  std::vector<std::unique_ptr<Completer>> completers;
  std::vector<std::unique_ptr<mtc::dds::Equipment>> all;
  for (int d = 0; d < devices; ++d) {
    completers.push_back(std::make_unique<Completer>());
    auto e = std::make_unique<mtc::dds::Equipment>(equipment_options(device("resp", d), domain),
                                                   quiet_callbacks());
    add_pairing(*e, device("req", d), interfaces);
    for (int k = 0; k < interfaces; ++k) {
      e->add_responder(interface_id(k), mtc::core::Service::MaterialLoad,
                       completers.back()->callbacks());
    }
    e->start();
    completers.back()->started();
    all.push_back(std::move(e));
  }
  wait_for_stop_signal(stop_signals);
  return 0;
}

pid_t spawn_peer(int devices, int interfaces, int domain) {
  std::vector<std::string> args{"--peer",
                                "--devices",
                                std::to_string(devices),
                                "--interfaces",
                                std::to_string(interfaces),
                                "--domain",
                                std::to_string(domain)};
  append_peer_flag(g_stepping, args);
  args.emplace_back("--middleware");
  args.emplace_back(mtc::dds::to_string(g_middleware));
  return exec_self("mtc-bench-scale", args);
}

void stop_peer(pid_t pid) {
  stop_child(pid, std::chrono::seconds(10));
}

bool wait_all_ready(const std::vector<mtc::dds::Requester*>& requesters,
                    std::chrono::steady_clock::duration timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    bool all = true;
    for (const auto* r : requesters) {
      all = all && r->counterpart_state() == mtc::core::InteractionState::Ready;
    }
    if (all) {
      return true;
    }
    if (std::chrono::steady_clock::now() > deadline) {
      return false;
    }
    // Discovery and pairing: outside every timed section but start-up's,
    // whose resolution this sets (1 ms against hundreds).
    std::this_thread::sleep_for(1ms);
  }
}

}  // namespace mtc::bench::scale
