// Starting and ending mtc-test-loss-peer (loss_peer_main.cpp) with its
// defaults: the responder "peer-ld" paired with "watch-ld". For the tests
// that define MTC_LOSS_PEER_PATH.
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>

namespace mtc::dds::testing {

// The peer on `domain`; its pid, or -1 when fork failed.
inline pid_t start_loss_peer(int domain) {
  const std::string id = std::to_string(domain);
  char* const argv[] = {const_cast<char*>(MTC_LOSS_PEER_PATH), const_cast<char*>(id.c_str()),
                        nullptr};
  const pid_t pid = fork();
  if (pid == 0) {
    execv(argv[0], argv);
    _exit(127);
  }
  return pid;
}

// Kills it (stopped or not) and waits for it.
inline void reap(pid_t pid) {
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
}

}  // namespace mtc::dds::testing
