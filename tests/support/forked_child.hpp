// Test helper: runs a function in a forked child process and returns what it exited with, so a test
// can exercise things that must not happen in the test process itself (SCHED_FIFO, mlockall,
// dropping privileges) or that need a second process (shared-memory queues).
// The child calls only the function and _exit(): no GoogleTest assertions there.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>

namespace rescue::test {

// Runs `child` in a forked child while the parent runs `parent` (it gets the child's pid, e.g. to
// notice that the child died early). Returns the child's exit status (0..255), or -1 when it could
// not run or was killed by a signal.
template <typename Child, typename Parent>
int run_with_child(Child child, Parent parent) {
  const pid_t pid = fork();
  if (pid < 0) return -1;
  if (pid == 0) _exit(child());
  parent(pid);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

template <typename Function>
int run_in_child(Function function) {
  return run_with_child(function, [](pid_t /*pid*/) {});
}

// True when the child `pid` has already exited (reaps nothing: WNOWAIT).
inline bool child_has_exited(pid_t pid) {
  siginfo_t info{};
  return waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 && info.si_pid == pid;
}

}  // namespace rescue::test
