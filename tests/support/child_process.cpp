#include "child_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <system_error>

namespace mtc::test {

namespace {

[[noreturn]] void throw_errno(const char* what) {
  throw std::system_error(errno, std::generic_category(), what);
}

// Only async-signal-safe calls between fork and exec (the test process has threads).
[[noreturn]] void exec_child(char* const* argv, int out_w, int err_w, pid_t parent) {
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() != parent) {
    _exit(127);
  }
  dup2(out_w, STDOUT_FILENO);
  dup2(err_w, STDERR_FILENO);
  sigset_t none;
  sigemptyset(&none);
  // Single-threaded child between fork and exec: sigprocmask is what applies.
  sigprocmask(SIG_SETMASK, &none, nullptr);  // NOLINT(concurrency-mt-unsafe)
  execv(argv[0], argv);
  _exit(127);
}

}  // namespace

ChildProcess::ChildProcess(std::vector<std::string> argv)
    : argv_(std::move(argv)),
      // Read before fork, on the test's main thread.
      verbose_(std::getenv("MTC_TEST_VERBOSE") != nullptr) {  // NOLINT(concurrency-mt-unsafe)
  std::vector<char*> cargv;
  for (auto& a : argv_) {
    cargv.push_back(a.data());
  }
  cargv.push_back(nullptr);
  int out_pipe[2];
  int err_pipe[2];
  if (pipe2(out_pipe, O_CLOEXEC) != 0) {
    throw_errno("pipe2");
  }
  if (pipe2(err_pipe, O_CLOEXEC) != 0) {
    throw_errno("pipe2");
  }
  const pid_t parent = getpid();
  pid_ = fork();
  if (pid_ < 0) {
    throw_errno("fork");
  }
  if (pid_ == 0) {
    exec_child(cargv.data(), out_pipe[1], err_pipe[1], parent);
  }
  close(out_pipe[1]);
  close(err_pipe[1]);
  out_fd_ = out_pipe[0];
  err_fd_ = err_pipe[0];
  // Through syscall(): bookworm's <sys/pidfd.h> lacks C linkage for C++.
  pidfd_ = static_cast<int>(syscall(SYS_pidfd_open, pid_, 0));
  if (pidfd_ < 0) {
    throw_errno("pidfd_open");
  }
}

ChildProcess::~ChildProcess() {
  if (running()) {
    // Ask first: a clean exit deletes the child's shared-memory segments,
    // SIGKILL would leave them in /dev/shm. SIGCONT in case it is stopped.
    kill(pid_, SIGTERM);
    kill(pid_, SIGCONT);
    if (!wait_exit(milliseconds(5000))) {
      kill(pid_, SIGKILL);
      reap(true);
    }
  }
  for (int fd : {out_fd_, err_fd_, pidfd_}) {
    if (fd >= 0) {
      close(fd);
    }
  }
}

void ChildProcess::drain(int& fd, std::string& partial, bool is_stdout) {
  char buf[4096];
  const ssize_t n = read(fd, buf, sizeof buf);
  if (n <= 0) {
    if (n < 0 && errno == EINTR) {
      return;
    }
    close(fd);
    fd = -1;
    if (!partial.empty() && is_stdout) {
      out_lines_.push_back(partial);
    }
    partial.clear();
    return;
  }
  if (!is_stdout) {
    err_text_.append(buf, static_cast<std::size_t>(n));
  }
  partial.append(buf, static_cast<std::size_t>(n));
  std::size_t pos = 0;
  while ((pos = partial.find('\n')) != std::string::npos) {
    if (is_stdout) {
      out_lines_.push_back(partial.substr(0, pos));
    }
    if (verbose_) {
      std::fprintf(stderr, "[%d %s] %s\n", pid_, is_stdout ? "out" : "err",
                   partial.substr(0, pos).c_str());
    }
    partial.erase(0, pos + 1);
  }
}

bool ChildProcess::pump(std::chrono::steady_clock::time_point deadline) {
  const std::size_t before = out_lines_.size();
  while (out_fd_ >= 0 || err_fd_ >= 0) {
    pollfd fds[2] = {{out_fd_, POLLIN, 0}, {err_fd_, POLLIN, 0}};
    const auto left =
        std::chrono::duration_cast<milliseconds>(deadline - std::chrono::steady_clock::now());
    const int rc = poll(fds, 2, static_cast<int>(std::max<long long>(0, left.count())));
    if (rc < 0 && errno == EINTR) {
      continue;
    }
    if (rc <= 0) {
      return true;  // timeout: more may come later
    }
    if (fds[0].revents != 0) {
      drain(out_fd_, out_partial_, true);
    }
    if (fds[1].revents != 0) {
      drain(err_fd_, err_partial_, false);
    }
    if (out_lines_.size() != before) {
      return true;
    }
  }
  return out_lines_.size() != before;
}

std::optional<std::string> ChildProcess::wait_for_line(const std::vector<std::string>& needles,
                                                       milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    for (; next_line_ < out_lines_.size(); ++next_line_) {
      const std::string& line = out_lines_[next_line_];
      bool all = true;
      for (const auto& n : needles) {
        all = all && line.find(n) != std::string::npos;
      }
      if (all) {
        return out_lines_[next_line_++];
      }
    }
    if (std::chrono::steady_clock::now() >= deadline) {
      return std::nullopt;
    }
    if (!pump(deadline) && out_fd_ < 0) {
      return std::nullopt;
    }
  }
}

bool ChildProcess::wait_for_stderr(const std::string& needle, milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  // pump() returns early only for stdout lines: wait in short slices.
  constexpr milliseconds kSlice{50};
  while (err_text_.find(needle) == std::string::npos) {
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline || (out_fd_ < 0 && err_fd_ < 0)) {
      return false;
    }
    pump(std::min(deadline, now + kSlice));
  }
  return true;
}

void ChildProcess::read_for(milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline && pump(deadline)) {
  }
}

void ChildProcess::send_signal(int signal_number) {
  if (running()) {
    kill(pid_, signal_number);
  }
}

bool ChildProcess::wait_stopped() {
  while (running()) {
    int status = 0;
    const pid_t r = waitpid(pid_, &status, WUNTRACED);
    if (r < 0 && errno == EINTR) {
      continue;
    }
    if (r != pid_) {
      return false;
    }
    if (WIFSTOPPED(status)) {
      return true;
    }
    exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  return false;
}

void ChildProcess::reap(bool block) {
  int status = 0;
  const pid_t r = waitpid(pid_, &status, block ? 0 : WNOHANG);
  if (r != pid_) {
    return;
  }
  exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::optional<int> ChildProcess::wait_exit(milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  // Output first (so nothing the child printed is lost), then the pidfd,
  // which becomes readable when the child terminates.
  while (out_fd_ >= 0 || err_fd_ >= 0) {
    if (std::chrono::steady_clock::now() >= deadline) {
      return std::nullopt;
    }
    pump(deadline);
  }
  while (running()) {
    pollfd p{pidfd_, POLLIN, 0};
    const auto left =
        std::chrono::duration_cast<milliseconds>(deadline - std::chrono::steady_clock::now());
    const int rc = poll(&p, 1, static_cast<int>(std::max<long long>(0, left.count())));
    if (rc < 0 && errno == EINTR) {
      continue;
    }
    if (rc == 0) {
      return std::nullopt;
    }
    reap(true);
  }
  return exit_code_;
}

std::string ChildProcess::stdout_text() const {
  std::string text;
  for (const auto& l : out_lines_) {
    text += l + "\n";
  }
  return text + out_partial_;
}

std::string ChildProcess::transcript() const {
  std::string text = "$";
  for (const auto& a : argv_) {
    text += " " + a;
  }
  text += "\n--- stdout ---\n";
  for (const auto& l : out_lines_) {
    text += l + "\n";
  }
  if (!out_partial_.empty()) {
    text += out_partial_ + "\n";
  }
  text += "--- stderr ---\n" + err_text_ + err_partial_;
  return text;
}

}  // namespace mtc::test
