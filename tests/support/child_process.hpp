// Test support: runs a program (usually the built rescue-motion) as a child process, optionally
// inside a named network namespace, and collects what it prints on stdout and stderr.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace rescue::testing {

class ChildProcess {
 public:
  ChildProcess() = default;
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  ~ChildProcess() {
    if (pid_ > 0) {
      (void)::kill(pid_, SIGKILL);
      int ignored = 0;
      (void)::waitpid(pid_, &ignored, 0);
    }
    if (out_ >= 0) ::close(out_);
    if (in_ >= 0) ::close(in_);
  }

  // Starts `argv` (argv[0] is the program's path); in `netns` when not empty. stdout and stderr go
  // to one pipe, read by wait_for_output() and output(); stdin comes from write_input().
  bool start(const std::vector<std::string>& argv, const std::string& netns = "") {
    int pipe_fds[2];
    int input_fds[2];
    if (::pipe2(pipe_fds, O_CLOEXEC) != 0) return false;
    if (::pipe2(input_fds, O_CLOEXEC) != 0) return false;
    pid_ = ::fork();
    if (pid_ < 0) return false;
    if (pid_ == 0) {
      ::dup2(pipe_fds[1], STDOUT_FILENO);
      ::dup2(pipe_fds[1], STDERR_FILENO);
      ::dup2(input_fds[0], STDIN_FILENO);
      if (!netns.empty()) {
        const int ns = ::open(("/run/netns/" + netns).c_str(), O_RDONLY | O_CLOEXEC);
        if (ns < 0 || ::setns(ns, CLONE_NEWNET) != 0) ::_exit(126);
      }
      std::vector<char*> args;
      for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
      args.push_back(nullptr);
      ::execv(args[0], args.data());
      ::_exit(127);
    }
    ::close(pipe_fds[1]);
    ::close(input_fds[0]);
    out_ = pipe_fds[0];
    in_ = input_fds[1];
    return true;
  }

  // Writes `text` to the child's stdin (e.g. fault commands for `rescue-motion sim`).
  bool write_input(const std::string& text) {
    return in_ >= 0 && ::write(in_, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  }

  // Reads output until it contains `text` or `timeout_ms` passed or the child closed its output.
  bool wait_for_output(const std::string& text, int timeout_ms) {
    timespec start{};
    ::clock_gettime(CLOCK_MONOTONIC, &start);
    while (output_.find(text) == std::string::npos) {
      timespec now{};
      ::clock_gettime(CLOCK_MONOTONIC, &now);
      const long elapsed_ms = (now.tv_sec - start.tv_sec) * 1000 + (now.tv_nsec - start.tv_nsec) / 1000000;
      if (elapsed_ms >= timeout_ms) return false;
      pollfd p{out_, POLLIN, 0};
      if (::poll(&p, 1, static_cast<int>(timeout_ms - elapsed_ms)) <= 0) continue;
      if (!read_some()) return output_.find(text) != std::string::npos;
    }
    return true;
  }

  // Sends `signal_number` and waits for the exit; returns the exit status, or -1 when killed.
  int stop(int signal_number) {
    if (pid_ <= 0) return -1;
    (void)::kill(pid_, signal_number);
    return wait_exit();
  }

  // Waits for the child to end by itself; returns its exit status, or -1 when killed by a signal.
  int wait_exit() {
    if (pid_ <= 0) return -1;
    while (read_some()) {
    }
    int status = 0;
    (void)::waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  const std::string& output() const { return output_; }
  // The running child's process id (-1 before start() and after it was reaped).
  pid_t pid() const { return pid_; }

 private:
  bool read_some() {
    std::array<char, 512> chunk{};
    const ssize_t n = ::read(out_, chunk.data(), chunk.size());
    if (n <= 0) return false;
    output_.append(chunk.data(), static_cast<std::size_t>(n));
    return true;
  }

  pid_t pid_{-1};
  int out_{-1};
  int in_{-1};
  std::string output_;
};

}  // namespace rescue::testing
