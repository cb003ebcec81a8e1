#include "raw_client.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <system_error>

namespace mtc::bridge::test {
namespace {

using Clock = std::chrono::steady_clock;

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string::npos) {
    return {};
  }
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

// Parses "Name: value" lines between `begin` and `end` of `text`.
std::map<std::string, std::string> parse_headers(const std::string& text, std::size_t begin,
                                                 std::size_t end) {
  std::map<std::string, std::string> headers;
  while (begin < end) {
    auto line_end = text.find("\r\n", begin);
    if (line_end == std::string::npos || line_end > end) {
      line_end = end;
    }
    const auto line = text.substr(begin, line_end - begin);
    const auto colon = line.find(':');
    if (colon != std::string::npos) {
      headers[lower(trim(line.substr(0, colon)))] = trim(line.substr(colon + 1));
    }
    begin = line_end + 2;
  }
  return headers;
}

// Splits off a response head ("HTTP/1.1 200 OK\r\n...\r\n\r\n") from buffer.
std::optional<HttpResponse> take_head(std::string& buffer) {
  const auto end = buffer.find("\r\n\r\n");
  if (end == std::string::npos) {
    return std::nullopt;
  }
  HttpResponse response;
  const auto line_end = buffer.find("\r\n");
  const auto status_line = buffer.substr(0, line_end);
  response.version = status_line.substr(0, status_line.find(' '));
  if (status_line.size() > 12) {
    response.status = static_cast<int>(std::strtol(status_line.c_str() + 9, nullptr, 10));
  }
  response.headers = parse_headers(buffer, line_end + 2, end);
  buffer.erase(0, end + 4);
  return response;
}

}  // namespace

RawClient::RawClient(std::uint16_t port, const ConnectOptions& options)
    : fd_(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0)) {
  if (fd_ < 0) {
    throw std::runtime_error(std::string("socket: ") + std::generic_category().message(errno));
  }
  if (options.receive_buffer > 0) {
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &options.receive_buffer,
                 sizeof options.receive_buffer);
  }
  if (options.source != nullptr) {
    sockaddr_in source{};
    source.sin_family = AF_INET;
    if (::inet_pton(AF_INET, options.source, &source.sin_addr) != 1 ||
        ::bind(fd_, reinterpret_cast<sockaddr*>(&source), sizeof source) != 0) {
      const std::string message = std::generic_category().message(errno);
      ::close(fd_);
      throw std::runtime_error(std::string("bind ") + options.source + ": " + message);
    }
  }
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    const std::string message = std::generic_category().message(errno);
    ::close(fd_);
    throw std::runtime_error("connect: " + message);
  }
  int one = 1;
  ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
}

RawClient::~RawClient() {
  close();
}

void RawClient::close() {
  if (fd_ >= 0) {
    ::close(fd_);
  }
  fd_ = -1;
}

void RawClient::reset() {
  if (fd_ < 0) {
    return;
  }
  linger option{1, 0};
  ::setsockopt(fd_, SOL_SOCKET, SO_LINGER, &option, sizeof option);
  close();
}

void RawClient::send(std::string_view bytes) {
  if (!try_send(bytes)) {
    throw std::runtime_error("send failed");
  }
}

bool RawClient::try_send(std::string_view bytes) noexcept {
  while (!bytes.empty()) {
    const auto n = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) {
      continue;
    }
    if (n <= 0) {
      return false;
    }
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
  return true;
}

void RawClient::shutdown_write() {
  ::shutdown(fd_, SHUT_WR);
}

bool RawClient::fill(Clock::time_point deadline) {
  if (eof_ || fd_ < 0) {
    return false;
  }
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
  if (left.count() <= 0) {
    return false;
  }
  pollfd pfd{fd_, POLLIN, 0};
  const int ready = ::poll(&pfd, 1, static_cast<int>(left.count()));
  if (ready <= 0) {
    return false;
  }
  char chunk[16384];
  const auto n = ::recv(fd_, chunk, sizeof chunk, 0);
  if (n <= 0) {
    eof_ = true;  // EOF or reset: either way the server is gone
    return false;
  }
  buffer_.append(chunk, static_cast<std::size_t>(n));
  return true;
}

bool RawClient::read_until(const std::function<bool(const std::string&)>& done,
                           std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  while (!done(buffer_)) {
    if (!fill(deadline)) {
      return done(buffer_);
    }
  }
  return true;
}

bool RawClient::wait_closed(std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  while (!eof_ && Clock::now() < deadline) {
    fill(deadline);
  }
  return eof_;
}

std::optional<HttpResponse> RawClient::read_response(std::chrono::milliseconds timeout,
                                                     bool head_only) {
  const auto deadline = Clock::now() + timeout;
  while (buffer_.find("\r\n\r\n") == std::string::npos) {
    if (!fill(deadline)) {
      return std::nullopt;
    }
  }
  auto response = take_head(buffer_);
  const auto length_text = response->header("content-length");
  if (head_only) {
    return response;
  }
  if (length_text.empty()) {  // body until close
    while (fill(deadline)) {
    }
    response->body.swap(buffer_);
    return response;
  }
  const auto length = static_cast<std::size_t>(std::stoull(length_text));
  while (buffer_.size() < length) {
    if (!fill(deadline)) {
      return std::nullopt;
    }
  }
  response->body = buffer_.substr(0, length);
  buffer_.erase(0, length);
  return response;
}

std::optional<HttpResponse> RawClient::read_stream_head(std::chrono::milliseconds timeout) {
  auto response = read_response(timeout, true);
  if (!response) {
    return response;
  }
  const auto type = response->header("content-type");
  const auto at = type.find("boundary=");
  if (at != std::string::npos) {
    boundary_ = type.substr(at + 9);
  }
  return response;
}

bool RawClient::dechunk() {
  bool progress = false;
  while (!last_chunk_) {
    const auto line_end = buffer_.find("\r\n");
    if (line_end == std::string::npos) {
      break;
    }
    const auto size = std::stoull(buffer_.substr(0, line_end), nullptr, 16);
    if (size == 0) {
      if (buffer_.size() < line_end + 4) {
        break;
      }
      last_chunk_ = true;
      buffer_.erase(0, line_end + 4);
      progress = true;
      break;
    }
    if (buffer_.size() < line_end + 2 + size + 2) {
      break;
    }
    body_.append(buffer_, line_end + 2, size);
    buffer_.erase(0, line_end + 2 + size + 2);
    progress = true;
  }
  return progress;
}

std::optional<Part> RawClient::read_part(std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  const std::string opener = "--" + boundary_ + "\r\n";
  for (;;) {
    dechunk();
    if (body_.compare(0, opener.size(), opener) == 0) {
      const auto head_end = body_.find("\r\n\r\n");
      if (head_end != std::string::npos) {
        Part part;
        part.headers = parse_headers(body_, opener.size(), head_end);
        const auto length = std::stoull(part.headers["content-length"]);
        if (body_.size() >= head_end + 4 + length + 2) {
          part.body = body_.substr(head_end + 4, length);
          body_.erase(0, head_end + 4 + length + 2);
          return part;
        }
      }
    }
    if (!fill(deadline)) {
      return std::nullopt;
    }
  }
}

bool RawClient::read_stream_end(std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  const std::string closer = "--" + boundary_ + "--";
  for (;;) {
    dechunk();
    if (last_chunk_ && body_.find(closer) != std::string::npos) {
      return true;
    }
    if (!fill(deadline)) {
      return false;
    }
  }
}

std::string get_request(std::string_view target, std::string_view extra_headers) {
  std::string request = "GET ";
  request.append(target);
  request.append(" HTTP/1.1\r\nHost: 127.0.0.1\r\n");
  request.append(extra_headers);
  request.append("\r\n");
  return request;
}

}  // namespace mtc::bridge::test
