// Streaming latency of the bridge's HTTP server: from a value being fed into
// the agent (what the DomainObserver callback does on a DDS transition) to
// the multipart part carrying it arriving at streaming HTTP clients
// (/sample?interval=0). Every client's arrival time is recorded.
//
//   scripts/netns-run.sh build/benchmarks/mtc-bench-bridge-stream
//       [--samples 2000] [--clients 4] [--io-threads 1]
//
// Bar (README): p50 < 200 us, p99 < 2 ms.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <condition_variable>
#include <iostream>
#include <mutex>
#include <random>
#include <stdexcept>
#include <thread>

#include "demo_cell.hpp"

namespace {

using namespace mtc::bridge::bench;
using Clock = std::chrono::steady_clock;

// One streaming connection whose reader thread stamps the arrival of the
// awaited observation (by its sequence number).
class StreamClient {
 public:
  explicit StreamClient(std::uint16_t port) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(port);
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (fd_ < 0 || ::connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
      throw std::runtime_error("cannot connect to the bridge");
    }
    int one = 1;
    ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    const std::string request =
        "GET /sample?interval=0&heartbeat=60000 HTTP/1.1\r\nHost: bench\r\n\r\n";
    if (::send(fd_, request.data(), request.size(), MSG_NOSIGNAL) < 0) {
      throw std::runtime_error("cannot send the stream request");
    }
    reader_ = std::thread([this] { read_loop(); });
  }
  ~StreamClient() {
    ::shutdown(fd_, SHUT_RDWR);
    reader_.join();
    ::close(fd_);
  }

  void expect(std::uint64_t sequence) {
    std::lock_guard<std::mutex> lock(mutex_);
    token_ = "sequence=\"" + std::to_string(sequence) + "\"";
    arrived_.reset();
    window_.clear();
  }

  // Arrival time of the awaited observation, waiting at most `timeout`.
  std::optional<Clock::time_point> wait(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait_for(lock, timeout, [&] { return arrived_.has_value(); });
    return arrived_;
  }

 private:
  void read_loop() {
    char chunk[65536];
    for (;;) {
      const auto n = ::recv(fd_, chunk, sizeof chunk, 0);
      const auto now = Clock::now();
      if (n <= 0) return;
      std::lock_guard<std::mutex> lock(mutex_);
      if (token_.empty() || arrived_) continue;
      window_.append(chunk, static_cast<std::size_t>(n));
      if (window_.find(token_) != std::string::npos) {
        arrived_ = now;
        cv_.notify_all();
      } else if (window_.size() > 4096) {
        window_.erase(0, window_.size() - 64);  // keep a tail: the token may straddle reads
      }
    }
  }

  int fd_ = -1;
  std::thread reader_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::string token_;
  std::string window_;
  std::optional<Clock::time_point> arrived_;
};

}  // namespace

int main(int argc, char** argv) try {
  const int samples = std::stoi(arg(argc, argv, "--samples", "2000"));
  const int client_count = std::stoi(arg(argc, argv, "--clients", "4"));
  const unsigned io_threads = static_cast<unsigned>(std::stoi(arg(argc, argv, "--io-threads", "1")));
  const std::string devices = arg(argc, argv, "--devices", MTC_DEMO_DEVICES);

  DemoCell cell(devices, io_threads);
  std::vector<std::unique_ptr<StreamClient>> clients;
  for (int i = 0; i < client_count; ++i) {
    clients.push_back(std::make_unique<StreamClient>(cell.port()));
  }

  std::mt19937 random(7);
  std::uniform_int_distribution<int> gap_us(200, 1200);
  std::vector<std::chrono::nanoseconds> first_client;
  std::vector<std::chrono::nanoseconds> all_clients;
  int lost = 0;
  const int warmup = 50;
  for (int k = 0; k < samples + warmup; ++k) {
    const std::uint64_t sequence = cell.agent().next_sequence();
    for (auto& client : clients) client->expect(sequence);
    const auto t0 = Clock::now();
    cell.feed_next(0);  // one item: each feed is one new observation
    for (std::size_t c = 0; c < clients.size(); ++c) {
      const auto t1 = clients[c]->wait(std::chrono::milliseconds(2000));
      if (!t1) {
        ++lost;
        continue;
      }
      if (k < warmup) continue;
      const auto latency = std::chrono::duration_cast<std::chrono::nanoseconds>(*t1 - t0);
      all_clients.push_back(latency);
      if (c == 0) first_client.push_back(latency);
    }
    // Spread the feeds so each measures an idle-to-busy wake-up, as a
    // handshake transition does, not a queue draining.
    std::this_thread::sleep_for(std::chrono::microseconds(gap_us(random)));
  }

  const auto one = summarize(first_client);
  const auto all = summarize(all_clients);
  auto print = [](const LatencySummary& s) {
    std::cout << "{\"samples\":" << s.samples << ",\"p50\":" << s.p50_us << ",\"p90\":" << s.p90_us
              << ",\"p99\":" << s.p99_us << ",\"max\":" << s.max_us << ",\"mean\":" << s.mean_us
              << "}";
  };
  std::cout << "{\"benchmark\":\"bridge_http_stream_latency\",\"clients\":" << client_count
            << ",\"io_threads\":" << io_threads << ",\"lost\":" << lost
            << ",\"first_client_us\":";
  print(one);
  std::cout << ",\"all_clients_us\":";
  print(all);
  std::cout << ",\"bar\":{\"max_p50_us\":200,\"max_p99_us\":2000},\"meets_bar\":"
            << ((lost == 0 && all.p50_us < 200 && all.p99_us < 2000) ? "true" : "false") << "}"
            << std::endl;
  return 0;
} catch (const std::exception& error) {
  std::cerr << "mtc-bench-bridge-stream: " << error.what() << "\n";
  return 1;
}
