#include "supervisor.hpp"

#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <ctime>
#include <exception>
#include <memory>
#include <optional>
#include <thread>

#include "console.hpp"
#include "equipment_link.hpp"
#include "local_link.hpp"

namespace mtc::cell {
namespace {

using Clock = std::chrono::steady_clock;

struct Child {
  StationId id;
  pid_t pid = -1;
  bool running = false;
  int exit_code = 0;
};

// "fastdds" when every station has it, else each station's, e.g.
// "machine fastdds, robot cyclone, feeder fastdds".
std::string middleware_text(const CellOptions& options) {
  const auto& m = options.middleware;
  if (m[0] == m[1] && m[1] == m[2]) return std::string(dds::to_string(m[0]));
  std::string text;
  for (const auto id : {StationId::Machine, StationId::Robot, StationId::Feeder}) {
    text += (text.empty() ? "" : ", ") + std::string(to_string(id)) + " " +
            std::string(dds::to_string(middleware_of(id, options)));
  }
  return text;
}

sigset_t control_signals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGCHLD);
  sigaddset(&set, SIGUSR1);  // a station thread says "done"
  return set;
}

int exit_code_of(int status) {
  if (WIFEXITED(status)) {
    return WEXITSTATUS(status);
  }
  if (WIFSIGNALED(status)) {
    return 128 + WTERMSIG(status);
  }
  return 1;
}

// fork + exec of this executable for one station. The child gets the
// supervisor's original signal mask back and dies with the supervisor.
pid_t spawn(StationId id, const std::vector<std::string>& args, const sigset_t& original_mask) {
  std::vector<std::string> argv_store = {"mtc-cell", "--station", std::string(to_string(id))};
  argv_store.insert(argv_store.end(), args.begin(), args.end());
  std::vector<char*> argv;
  argv.reserve(argv_store.size() + 1);
  for (auto& a : argv_store) {
    argv.push_back(a.data());
  }
  argv.push_back(nullptr);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid != 0) {
    return pid;  // parent (or -1)
  }
  pthread_sigmask(SIG_SETMASK, &original_mask, nullptr);
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (getppid() != parent) {
    _exit(1);
  }
  execv("/proc/self/exe", argv.data());
  _exit(127);
}

timespec to_timespec(Clock::duration d) {
  if (d < Clock::duration::zero()) {
    d = Clock::duration::zero();
  }
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(d).count();
  return timespec{static_cast<time_t>(ns / 1000000000), static_cast<long>(ns % 1000000000)};
}

class Supervisor {
 public:
  Supervisor(const CellOptions& options, std::vector<Child> children)
      : options_(options), children_(std::move(children)) {}

  int run(const sigset_t& signals) {
    const auto started = Clock::now();
    schedule_freeze(started);
    while (any_running()) {
      const auto now = Clock::now();
      Clock::duration wait = std::chrono::seconds(1);
      if (stopping_) {
        wait = std::min<Clock::duration>(wait, (rest_stopped_ ? kill_at_ : rest_at_) - now);
      }
      if (!stopping_ && freeze_at_) {
        wait = std::min<Clock::duration>(wait, *freeze_at_ - now);
      }
      if (!stopping_ && options_.duration_s > 0) {
        wait = std::min<Clock::duration>(wait,
                                         started + std::chrono::seconds(options_.duration_s) - now);
      }
      const timespec ts = to_timespec(wait);
      const int sig = sigtimedwait(&signals, nullptr, &ts);
      if ((sig == SIGINT || sig == SIGTERM) && !stopping_) {
        begin_stop("stop requested", 0);
      }
      reap();
      if (!stopping_ && options_.duration_s > 0 &&
          Clock::now() >= started + std::chrono::seconds(options_.duration_s)) {
        begin_stop("duration reached", 0);
      }
      if (stopping_ && !rest_stopped_ && (!machine().running || Clock::now() >= rest_at_)) {
        stop_the_rest();
      }
      if (stopping_ && rest_stopped_ && Clock::now() >= kill_at_) {
        kill_survivors();
      }
      if (!stopping_ && freeze_at_ && Clock::now() >= *freeze_at_) {
        freeze_or_thaw();
      }
    }
    return exit_code_;
  }

 private:
  bool any_running() const {
    return std::any_of(children_.begin(), children_.end(), [](const auto& c) { return c.running; });
  }

  // Scenario 6 staged for real: a station process is frozen (SIGSTOP) long
  // enough for its peers' liveliness lease to expire, then resumed.
  void schedule_freeze(Clock::time_point from) {
    if (options_.freeze_every_s <= 0) {
      return;
    }
    // Seeded jitter: between 0.5 and 1.5 times the period.
    rng_state_ = rng_state_ * 6364136223846793005ULL + 1442695040888963407ULL;
    const auto period_ms = options_.freeze_every_s * 1000;
    const auto jitter = static_cast<long>((rng_state_ >> 33) % static_cast<unsigned>(period_ms));
    freeze_at_ = from + std::chrono::milliseconds(period_ms / 2 + jitter);
  }

  void freeze_or_thaw() {
    if (frozen_) {
      kill(frozen_->pid, SIGCONT);
      print_line("cell", format("%s resumes after %.1f s frozen",
                                std::string(to_string(frozen_->id)).c_str(),
                                std::chrono::duration<double>(freeze_length()).count()));
      frozen_ = nullptr;
      schedule_freeze(Clock::now());
      return;
    }
    // Robot and feeder take turns; the machine keeps the cycle's account.
    Child& c = children_[(freezes_++ % 2 == 0) ? 1 : 0];
    if (!c.running) {
      return;
    }
    kill(c.pid, SIGSTOP);
    frozen_ = &c;
    print_line("cell", format("!! %s frozen (SIGSTOP) for %.1f s: loss of communication, "
                              "scenario 6",
                              std::string(to_string(c.id)).c_str(),
                              std::chrono::duration<double>(freeze_length()).count()));
    freeze_at_ = Clock::now() + freeze_length();
  }

  // A lease and 3 s: long enough to be declared lost for certain.
  Clock::duration freeze_length() const {
    return options_.timing.lease() + std::chrono::seconds(3);
  }

  Child& machine() {
    return *std::find_if(children_.begin(), children_.end(),
                         [](const Child& c) { return c.id == StationId::Machine; });
  }

  // The machine first: it drives the cycle, and a handshake it has in
  // flight when its counterpart leaves would count as a failure it can no
  // longer recover from. The others once it is gone (or after 2 s).
  void begin_stop(const char* why, int code) {
    if (frozen_) {
      kill(frozen_->pid, SIGCONT);  // a stopped process cannot act on SIGTERM
    }
    frozen_ = nullptr;
    stopping_ = true;
    exit_code_ = code;
    rest_at_ = Clock::now() + std::chrono::seconds(2);
    print_line("cell", format("%s: stopping every station", why));
    if (machine().running) {
      kill(machine().pid, SIGTERM);
    }
  }

  void stop_the_rest() {
    rest_stopped_ = true;
    kill_at_ = Clock::now() + std::chrono::seconds(5);
    for (const auto& c : children_) {
      if (c.running) {
        kill(c.pid, SIGTERM);
      }
    }
  }

  void kill_survivors() {
    for (auto& c : children_) {
      if (!c.running) {
        continue;
      }
      print_line("cell",
                 format("%.*s (pid %d) did not stop in time: killed",
                        static_cast<int>(to_string(c.id).size()), to_string(c.id).data(), c.pid));
      kill(c.pid, SIGKILL);
    }
    kill_at_ = Clock::now() + std::chrono::seconds(5);
  }

  void reap() {
    for (auto& c : children_) {
      if (!c.running) {
        continue;
      }
      int status = 0;
      if (waitpid(c.pid, &status, WNOHANG) != c.pid) {
        continue;
      }
      c.running = false;
      c.exit_code = exit_code_of(status);
      if (stopping_) {
        continue;
      }
      const auto name = to_string(c.id);
      if (c.id == StationId::Machine) {
        begin_stop("the machine finished its cycles", c.exit_code);
      } else {
        print_line("cell", format("%.*s exited unexpectedly (code %d)",
                                  static_cast<int>(name.size()), name.data(), c.exit_code));
        begin_stop("a station is gone", 1);
      }
    }
  }

  const CellOptions& options_;
  std::vector<Child> children_;  // feeder, robot, machine
  std::optional<Clock::time_point> freeze_at_;
  Child* frozen_ = nullptr;
  unsigned freezes_ = 0;
  std::uint64_t rng_state_ = options_.seed;
  bool stopping_ = false;
  bool rest_stopped_ = false;  // SIGTERM sent to the stations after the machine
  int exit_code_ = 0;
  Clock::time_point rest_at_{};
  Clock::time_point kill_at_{};
};

// Blocks the control signals in the calling thread (and every thread it
// starts afterwards) so they are taken by sigwait, never by a handler.
sigset_t block_control_signals(sigset_t* original) {
  const sigset_t set = control_signals();
  pthread_sigmask(SIG_BLOCK, &set, original);
  return set;
}

// Waits for a stop signal, for a station thread's SIGUSR1, or for the end of
// `duration_s`.
void wait_for_end(const sigset_t& set, int duration_s) {
  const auto until = Clock::now() + std::chrono::seconds(duration_s);
  for (;;) {
    const timespec ts = to_timespec(duration_s > 0 ? until - Clock::now() : std::chrono::hours(1));
    const int sig = sigtimedwait(&set, nullptr, &ts);
    if (sig == SIGINT || sig == SIGTERM || sig == SIGUSR1) {
      return;
    }
    if (duration_s > 0 && Clock::now() >= until) {
      return;
    }
  }
}

}  // namespace

int supervise(const CellOptions& options, const std::vector<std::string>& station_args) {
  sigset_t original;
  const sigset_t set = block_control_signals(&original);
  std::vector<Child> children;
  // Responders first: the machine's first requests then find them READY.
  for (StationId id : {StationId::Feeder, StationId::Robot, StationId::Machine}) {
    const pid_t pid = spawn(id, station_args, original);
    if (pid < 0) {
      print_line("cell", format("cannot start a station: fork failed (errno %d)", errno));
      for (auto& c : children) {
        kill(c.pid, SIGTERM);
      }
      for (auto& c : children) {
        waitpid(c.pid, nullptr, 0);
      }
      return 1;
    }
    children.push_back({id, pid, true, 0});
  }
  print_line("cell", format("stations started: machine pid %d, robot pid %d, feeder pid %d "
                            "(DDS domain %d, transport %s, middleware %s)",
                            children[2].pid, children[1].pid, children[0].pid, options.domain_id,
                            std::string(qos::to_string(options.transport)).c_str(),
                            middleware_text(options).c_str()));
  const int rc = Supervisor(options, std::move(children)).run(set);
  print_line("cell", format("all stations stopped, exit code %d", rc));
  pthread_sigmask(SIG_SETMASK, &original, nullptr);
  return rc;
}

int run_station_process(StationId id, const CellOptions& options) {
  sigset_t original;
  const sigset_t set = block_control_signals(&original);
  std::unique_ptr<Link> link;
  try {
    link = make_equipment_link(id, options);
  } catch (const std::exception& e) {
    print_line(to_string(id), format("cannot start: %s", e.what()));
    return 1;
  }
  Stopper stop;
  std::atomic<int> rc{0};
  std::thread worker([&] {
    rc.store(run_station(id, *link, options, stop));
    kill(getpid(), SIGUSR1);
  });
  wait_for_end(set, 0);
  stop.stop();
  worker.join();
  link.reset();  // the equipment leaves the domain before the process exits
  return rc.load();
}

int run_all_in_process(const CellOptions& options, bool local) {
  sigset_t original;
  const sigset_t set = block_control_signals(&original);
  std::unique_ptr<LocalBus> bus;
  std::vector<std::unique_ptr<Link>> links;
  const StationId ids[] = {StationId::Feeder, StationId::Robot, StationId::Machine};
  try {
    if (local) {
      core::MachineOptions mo;
      mo.limits.fail_ack = std::chrono::seconds(2);
      bus = std::make_unique<LocalBus>(mo);
    } else {
      for (StationId id : ids) {
        links.push_back(make_equipment_link(id, options));
      }
    }
  } catch (const std::exception& e) {
    print_line("cell", format("cannot start: %s", e.what()));
    return 1;
  }
  Stopper stop;
  std::atomic<int> rc{0};
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < 3; ++i) {
    Link* link = local ? static_cast<Link*>(bus.get()) : links[i].get();
    threads.emplace_back([&options, &stop, &rc, link, id = ids[i]] {
      const int code = run_station(id, *link, options, stop);
      if (id == StationId::Machine) {
        rc.store(code);
        kill(getpid(), SIGUSR1);
      }
    });
  }
  wait_for_end(set, options.duration_s);
  stop.stop();
  for (auto& t : threads) {
    t.join();
  }
  return rc.load();
}

}  // namespace mtc::cell
