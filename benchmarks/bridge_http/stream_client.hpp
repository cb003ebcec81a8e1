// A streaming HTTP client for the benchmarks: raw socket, a reader thread
// that timestamps (at recv) the arrival of an awaited piece of text.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

namespace mtc::bridge::bench {

using Clock = std::chrono::steady_clock;

// One streaming connection whose reader thread stamps the arrival of the
// awaited text (a sequence number, a value) in the stream.
class StreamClient {
 public:
  explicit StreamClient(std::uint16_t port,
                        const std::string& target = "/sample?interval=0&heartbeat=60000")
      : fd_(::socket(AF_INET, SOCK_STREAM, 0)) {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(port);
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (fd_ < 0 || ::connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
      throw std::runtime_error("cannot connect to the bridge");
    }
    int one = 1;
    ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    const std::string request = "GET " + target + " HTTP/1.1\r\nHost: bench\r\n\r\n";
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
  StreamClient(const StreamClient&) = delete;
  StreamClient& operator=(const StreamClient&) = delete;

  struct Arrival {
    Clock::time_point steady;
    std::chrono::system_clock::time_point wall;  // comparable with DDS source times
  };

  void expect(std::string token) {
    std::lock_guard<std::mutex> lock(mutex_);
    token_ = std::move(token);
    arrived_.reset();
    window_.clear();
  }

  // Arrival time of the awaited text, waiting at most `timeout`.
  std::optional<Arrival> wait(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait_for(lock, timeout, [&] { return arrived_.has_value(); });
    return arrived_;
  }

 private:
  void read_loop() {
    char chunk[65536];
    for (;;) {
      const auto n = ::recv(fd_, chunk, sizeof chunk, 0);
      const Arrival now{Clock::now(), std::chrono::system_clock::now()};
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
  std::optional<Arrival> arrived_;
};

}  // namespace mtc::bridge::bench
