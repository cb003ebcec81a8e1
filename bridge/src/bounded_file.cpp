#include "mtc/bridge/bounded_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

namespace mtc::bridge {
namespace {

// Closes the descriptor on every path out.
class Descriptor {
 public:
  explicit Descriptor(int fd) noexcept : fd_(fd) {}
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  int get() const noexcept { return fd_; }

 private:
  int fd_;
};

}  // namespace

std::optional<std::string> read_bounded_file(const std::string& path, std::size_t limit,
                                             std::string_view what, std::string& error) {
  const std::string file(what);
  // O_NONBLOCK: opening a FIFO nobody writes to must not hang; reads below
  // block again so that a pipe with a writer is read to its end.
  const Descriptor fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK));
  if (fd.get() < 0) {
    error = "cannot open " + file + ": " + std::generic_category().message(errno);
    return std::nullopt;
  }
  struct stat info {};
  if (::fstat(fd.get(), &info) != 0) {
    error = "cannot read " + file + ": " + std::generic_category().message(errno);
    return std::nullopt;
  }
  if (S_ISDIR(info.st_mode)) {
    error = file + " is a directory";
    return std::nullopt;
  }
  const auto too_large = [&] {
    error = file + " is larger than " + std::to_string(limit) + " bytes";
    return std::nullopt;
  };
  if (S_ISREG(info.st_mode) && static_cast<std::size_t>(info.st_size) > limit) return too_large();
  const int flags = ::fcntl(fd.get(), F_GETFL);
  if (flags >= 0) ::fcntl(fd.get(), F_SETFL, flags & ~O_NONBLOCK);

  std::string text;
  char chunk[65536];
  for (;;) {
    const ssize_t got = ::read(fd.get(), chunk, sizeof chunk);
    if (got == 0) break;
    if (got < 0) {
      if (errno == EINTR) continue;
      error = "cannot read " + file + ": " + std::generic_category().message(errno);
      return std::nullopt;
    }
    if (text.size() + static_cast<std::size_t>(got) > limit) return too_large();
    text.append(chunk, static_cast<std::size_t>(got));
  }
  return text;
}

}  // namespace mtc::bridge
