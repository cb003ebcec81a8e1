// Many streaming clients at once: --clients (default 1,000) connections to
// /sample?interval=0 of the demo cell, from 20 loopback source addresses
// (the server allows 64 connections per address), all read by one epoll
// thread that stamps when each client's part carrying a new value arrives.
// For each fed value: the latency to every client; the process's RSS
// before the clients, when streaming starts, after the last value and once
// the clients have left (no growth while streaming is the bar).
//
//   scripts/netns-run.sh build/benchmarks/mtc-bench-bridge-fanout [options]
//
// Bar (issue 9 section 5): p99 over all clients < 10 ms, none lost, RSS at
// the end of streaming within 5 % (or 2 MiB) of its start.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <iostream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "demo_cell.hpp"
#include "mtc/bench/cli.hpp"
#include "mtc/bench/proc_cpu.hpp"

using mtc::bench::rss_kb;
using mtc::bridge::bench::DemoCell;
using mtc::bridge::bench::LatencySummary;
using mtc::bridge::bench::print_summary;
using mtc::bridge::bench::summarize;
using Clock = std::chrono::steady_clock;

namespace {

constexpr const char* kAbout =
    "Many streaming clients at once: N connections to /sample?interval=0 of the demo\n"
    "cell (20 loopback source addresses), read by one epoll thread. For each value fed\n"
    "into the agent, the time until each client has the part carrying it; the RSS of\n"
    "this process (server and clients) before the clients connect, when streaming\n"
    "starts, after the last value and after the clients left. Runs inside the\n"
    "loopback-only namespace (scripts/netns-run.sh). One JSON line on stdout:\n"
    "  {\"benchmark\":\"bridge_http_fanout\",\"clients\",\"lost\",\"all_clients_us\":{p50,...},\n"
    "   \"last_client_us\":{...},\"rss_kb\":{...},\"cpu_us_per_part\",\"meets_bar\",...}\n"
    "(cpu_us_per_part: CPU time of the whole process, server and clients, per part\n"
    "delivered while timed: what the machine's other load does not inflate).\n"
    "(bar: p99 over all clients < 10 ms, none lost, no RSS growth while streaming).";

int connect_stream(std::uint16_t port, const std::string& source) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) {
    throw std::runtime_error("cannot create a socket (raise ulimit -n?)");
  }
  sockaddr_in address{};
  address.sin_family = AF_INET;
  ::inet_pton(AF_INET, source.c_str(), &address.sin_addr);
  if (::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    ::close(fd);
    throw std::runtime_error("cannot bind to " + source);
  }
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    ::close(fd);
    throw std::runtime_error("cannot connect to the bridge");
  }
  int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  const std::string request =
      "GET /sample?interval=0&heartbeat=60000 HTTP/1.1\r\nHost: bench\r\n\r\n";
  if (::send(fd, request.data(), request.size(), MSG_NOSIGNAL) < 0) {
    ::close(fd);
    throw std::runtime_error("cannot send the stream request");
  }
  return fd;
}

// Every client's stream, read by one epoll thread; per fed value, the
// arrival of the awaited token at each client.
class Fanout {
 public:
  Fanout(std::uint16_t port, int clients)
      : epoll_(::epoll_create1(EPOLL_CLOEXEC)), windows_(static_cast<std::size_t>(clients)) {
    for (int i = 0; i < clients; ++i) {
      const int fd = connect_stream(port, "127.0.0." + std::to_string(2 + i % 20));
      fds_.push_back(fd);
      epoll_event event{};
      event.events = EPOLLIN;
      event.data.u32 = static_cast<std::uint32_t>(i);
      ::epoll_ctl(epoll_, EPOLL_CTL_ADD, fd, &event);
    }
    arrived_.assign(fds_.size(), Clock::time_point{});
    reader_ = std::thread([this] { read_loop(); });
  }
  ~Fanout() {
    stop_.store(true);
    for (int fd : fds_) {
      ::shutdown(fd, SHUT_RDWR);
    }
    reader_.join();
    for (int fd : fds_) {
      ::close(fd);
    }
    ::close(epoll_);
  }
  Fanout(const Fanout&) = delete;  // owns the sockets and the reader thread
  Fanout& operator=(const Fanout&) = delete;

  void expect(const std::string& token) {
    std::lock_guard<std::mutex> lock(mutex_);
    token_ = token;
    count_ = 0;
    std::fill(arrived_.begin(), arrived_.end(), Clock::time_point{});
    for (auto& w : windows_) {
      w.clear();
    }
  }

  // Arrival times (epoch = not arrived) once every client has the token or
  // `timeout` passed.
  std::vector<Clock::time_point> wait(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    all_.wait_for(lock, timeout, [&] { return count_ == fds_.size(); });
    return arrived_;
  }

 private:
  void read_loop() {
    std::vector<epoll_event> events(256);
    static char chunk[65536];
    while (!stop_.load()) {
      const int n = ::epoll_wait(epoll_, events.data(), static_cast<int>(events.size()), 100);
      for (int e = 0; e < n; ++e) {
        const auto i = events[static_cast<std::size_t>(e)].data.u32;
        const auto got = ::recv(fds_[i], chunk, sizeof chunk, MSG_DONTWAIT);
        const auto now = Clock::now();
        if (got <= 0) {
          if (got == 0) {
            ::epoll_ctl(epoll_, EPOLL_CTL_DEL, fds_[i], nullptr);  // closed
          }
          continue;
        }
        on_data(i, chunk, static_cast<std::size_t>(got), now);
      }
    }
  }

  void on_data(std::uint32_t i, const char* data, std::size_t size, Clock::time_point now) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (token_.empty() || arrived_[i] != Clock::time_point{}) {
      return;
    }
    auto& window = windows_[i];
    window.append(data, size);
    if (window.find(token_) != std::string::npos) {
      arrived_[i] = now;
      if (++count_ == fds_.size()) {
        all_.notify_all();
      }
    } else if (window.size() > 4096) {
      window.erase(0, window.size() - 64);  // keep a tail: the token may straddle reads
    }
  }

  int epoll_ = -1;
  std::vector<int> fds_;
  std::vector<std::string> windows_;
  std::thread reader_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::condition_variable all_;
  std::string token_;
  std::vector<Clock::time_point> arrived_;
  std::size_t count_ = 0;
};

void raise_fd_limit() {
  rlimit limit{};
  if (::getrlimit(RLIMIT_NOFILE, &limit) == 0 && limit.rlim_cur < limit.rlim_max) {
    limit.rlim_cur = limit.rlim_max;
    ::setrlimit(RLIMIT_NOFILE, &limit);
  }
}

// CPU time (user + system) of this process: a cost the machine's other
// load does not inflate, unlike the latencies.
double cpu_seconds() {
  rusage usage{};
  if (::getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_usec) / 1e6;
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// What one run measured: per fed value, each client's latency and the
// slowest client's; the clients that never got it; RSS around streaming.
struct FanoutRun {
  std::vector<std::chrono::nanoseconds> all_clients;
  double cpu_seconds = 0;  // the process (server and clients) over the timed values
  std::vector<std::chrono::nanoseconds> last_client;
  long rss_start = 0;
  long rss_end = 0;
  int lost = 0;
};

FanoutRun measure(DemoCell& cell, int client_count, int feeds) {
  FanoutRun run;
  Fanout fanout(cell.port(), client_count);
  const int warmup = 5;  // the first parts carry every item's current value
  for (int k = 0; k < warmup + feeds; ++k) {
    if (k == warmup) {
      run.rss_start = rss_kb();
      run.cpu_seconds = -cpu_seconds();
    }
    fanout.expect("sequence=\"" + std::to_string(cell.agent().next_sequence()) + "\"");
    const auto t0 = Clock::now();
    cell.feed_next(0);
    const auto arrivals = fanout.wait(std::chrono::milliseconds(k < warmup ? 10000 : 5000));
    if (k < warmup) {
      continue;
    }
    auto latest = std::chrono::nanoseconds{0};
    for (const auto& t : arrivals) {
      if (t == Clock::time_point{}) {
        ++run.lost;
        continue;
      }
      const auto latency = std::chrono::duration_cast<std::chrono::nanoseconds>(t - t0);
      run.all_clients.push_back(latency);
      latest = std::max(latest, latency);
    }
    run.last_client.push_back(latest);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  run.cpu_seconds += cpu_seconds();
  run.rss_end = rss_kb();
  return run;
}

}  // namespace

int main(int argc, char** argv) try {
  int client_count = 1000;
  int feeds = 100;
  int io_threads = 1;
  std::string devices = MTC_DEMO_DEVICES;
  mtc::bench::Cli cli("mtc-bench-bridge-fanout", kAbout);
  cli.integer("--clients", client_count, 1, 1000, "streaming clients at once")
      .integer("--feeds", feeds, 1, 1000000, "values fed and timed")
      .integer("--io-threads", io_threads, 1, 64, "the HTTP server's io threads")
      .text("--devices", "FILE", devices, "MTConnect Devices file of the demo cell");
  if (const auto exit_code = cli.parse(argc, argv)) {
    return *exit_code;
  }
  raise_fd_limit();
  DemoCell cell(devices, static_cast<unsigned>(io_threads));
  const long rss_before = rss_kb();
  const FanoutRun run = measure(cell, client_count, feeds);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the server closes its side
  const long rss_after = rss_kb();
  const LatencySummary all = summarize(run.all_clients);
  const long growth = run.rss_end - run.rss_start;
  const bool flat = growth <= std::max(2048L, run.rss_start / 20);
  std::cout << "{\"benchmark\":\"bridge_http_fanout\",\"clients\":" << client_count
            << ",\"feeds\":" << feeds << ",\"io_threads\":" << io_threads
            << ",\"lost\":" << run.lost << ",\"all_clients_us\":";
  print_summary(std::cout, all);
  std::cout << ",\"last_client_us\":";
  print_summary(std::cout, summarize(run.last_client));
  std::cout << ",\"rss_kb\":{\"before_clients\":" << rss_before
            << ",\"streaming_start\":" << run.rss_start << ",\"streaming_end\":" << run.rss_end
            << ",\"after_clients_left\":" << rss_after
            << "},\"rss_growth_while_streaming_kb\":" << growth << ",\"cpu_us_per_part\":"
            << (run.all_clients.empty()
                    ? 0.0
                    : run.cpu_seconds * 1e6 / static_cast<double>(run.all_clients.size()))
            << ",\"bar\":{\"max_p99_us\":10000,\"rss_growth\":\"<= max(2 MiB, 5 %)\"}"
            << ",\"meets_bar\":"
            << ((run.lost == 0 && all.p99_us < 10000 && flat) ? "true" : "false") << "}"
            << std::endl;
  return 0;
} catch (const std::exception& error) {
  std::cerr << "mtc-bench-bridge-fanout: " << error.what() << "\n";
  return 1;
}
