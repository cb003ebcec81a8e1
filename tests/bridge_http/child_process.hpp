// Runs a program (mtc-bridge) as a child process with its stdout and stderr
// on pipes, so tests can wait for a line, signal it and collect its exit.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace mtc::bridge::test {

class ChildProcess {
 public:
  // Starts `program` with `args`; throws std::runtime_error when it cannot.
  ChildProcess(const std::string& program, const std::vector<std::string>& args);
  ~ChildProcess();  // SIGKILL and reap if still running
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // Waits for a stdout line containing `needle`; returns it.
  std::optional<std::string> wait_for_line(const std::string& needle,
                                           std::chrono::milliseconds timeout);
  void signal(int signal_number);
  // Exit code (or 128 + signal) once the process ended within the timeout.
  std::optional<int> wait_exit(std::chrono::milliseconds timeout);

  const std::string& out() const noexcept { return out_; }
  const std::string& err() const noexcept { return err_; }

 private:
  void drain(std::chrono::milliseconds timeout);  // one poll over both pipes

  pid_t pid_ = -1;
  int out_fd_ = -1;
  int err_fd_ = -1;
  std::string out_;
  std::string err_;
  std::size_t scanned_ = 0;
  std::optional<int> exit_code_;
};

}  // namespace mtc::bridge::test
