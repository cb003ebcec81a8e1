// A child process for the tests that run the project's programs (tests/tools:
// `mtc`; tests/bridge_http: `mtc-bridge`): started with fork/exec, its
// stdout and stderr captured through pipes, read line by line with poll()
// against deadlines. Tests synchronise on the lines a child prints and on its
// exit status, never on sleeps. A child that outlives its ChildProcess is
// stopped in the destructor (SIGTERM, then SIGKILL if it does not exit within
// 5 s), and PR_SET_PDEATHSIG kills it if the test process dies first.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace mtc::test {

using std::chrono::milliseconds;

class ChildProcess {
 public:
  // argv[0] is the executable's path. Throws std::system_error on failure.
  explicit ChildProcess(std::vector<std::string> argv);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }

  // Next stdout line (after the last one returned) that contains every needle;
  // nullopt when the timeout passes or the child closes stdout first.
  std::optional<std::string> wait_for_line(const std::vector<std::string>& needles,
                                           milliseconds timeout);
  // Waits until what the child wrote to stderr contains `needle` (for
  // reports that have no stdout line of their own); false at the timeout or
  // once the child has closed both pipes without writing it.
  bool wait_for_stderr(const std::string& needle, milliseconds timeout);
  // Reads what the child writes for `timeout` without consuming any line: a
  // later wait_for_line still finds what arrived meanwhile. For keeping the
  // pipes of a chatty child from filling while the test waits elsewhere.
  void read_for(milliseconds timeout);
  // Every stdout line read so far.
  const std::vector<std::string>& lines() const { return out_lines_; }

  void send_signal(int signal_number);
  // Blocks until the child is stopped (SIGSTOP, raised by itself or sent):
  // true, or false when it terminated instead. Call only when it is about to
  // stop or has (e.g. after a line that says so).
  bool wait_stopped();
  // Exit code, 128 + signal when killed by a signal, nullopt at timeout. Reads
  // the remaining output on the way.
  std::optional<int> wait_exit(milliseconds timeout);
  bool running() const { return !exit_code_.has_value(); }

  // Command line, stdout and stderr: for assertion messages.
  std::string transcript() const;
  // Everything read so far from stdout (lines joined by '\n') and stderr.
  std::string stdout_text() const;
  std::string stderr_text() const { return err_text_; }

 private:
  // Reads whatever is available until `deadline`, or returns early once a new
  // complete line arrived on stdout. False once nothing more can come.
  bool pump(std::chrono::steady_clock::time_point deadline);
  void drain(int& fd, std::string& partial, bool is_stdout);
  void reap(bool block);

  std::vector<std::string> argv_;
  pid_t pid_ = -1;
  int pidfd_ = -1;
  int out_fd_ = -1;
  int err_fd_ = -1;
  std::string out_partial_;
  std::string err_partial_;
  std::string err_text_;
  std::vector<std::string> out_lines_;
  std::size_t next_line_ = 0;
  std::optional<int> exit_code_;
  bool verbose_ = false;  // MTC_TEST_VERBOSE set: echo the child's lines to stderr
};

}  // namespace mtc::test
