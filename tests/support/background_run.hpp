// `rescue-motion run` started in the background by a test, as an operator would from a shell: its
// output goes to a log file the test reads while it runs (tests only: allocates freely).
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace rescue::test {

inline std::string read_text_file(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The number after "pid " on the first line of `out` holding `text` (0 when none), e.g. the pid in
// "supervisor: started rc-rescue (pid 1234)".
inline pid_t pid_on_line(const std::string& out, const std::string& text) {
  const std::size_t at = out.find(text);
  if (at == std::string::npos) return 0;
  const std::size_t p = out.find("pid ", at);
  const std::size_t eol = out.find('\n', at);
  if (p == std::string::npos || p > eol) return 0;
  return static_cast<pid_t>(std::atoi(out.c_str() + p + 4));
}

class BackgroundRun {
 public:
  // Starts RESCUE_BINARY_DIR/rescue-motion with `args`, output to `log`.
  BackgroundRun(const std::vector<std::string>& args, std::string log) : log_(std::move(log)) {
    const std::string binary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";
    pid_ = ::fork();
    if (pid_ == 0) {
      const int fd = ::open(log_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
      (void)::dup2(fd, 1);
      (void)::dup2(fd, 2);
      std::vector<char*> argv;
      argv.push_back(const_cast<char*>(binary.c_str()));
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      ::execv(binary.c_str(), argv.data());
      ::_exit(127);
    }
  }
  ~BackgroundRun() {
    if (pid_ > 0 && !reaped_) {
      (void)::kill(pid_, SIGKILL);
      (void)::waitpid(pid_, nullptr, 0);
    }
  }
  BackgroundRun(const BackgroundRun&) = delete;
  BackgroundRun& operator=(const BackgroundRun&) = delete;

  pid_t pid() const { return pid_; }
  std::string output() const { return read_text_file(log_); }
  // True once the output holds `text` (checked every 10 ms up to `limit`).
  bool wait_for(const std::string& text, std::chrono::milliseconds limit) const {
    const auto until = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < until) {
      if (output().find(text) != std::string::npos) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return output().find(text) != std::string::npos;
  }
  // The number after "pid " on the first line of the output holding `text` (0 when none).
  pid_t pid_on_line(const std::string& text) const { return rescue::test::pid_on_line(output(), text); }
  // Waits for the end; the exit status, or -signal when killed.
  int wait_exit() {
    int status = 0;
    (void)::waitpid(pid_, &status, 0);
    reaped_ = true;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  }

 private:
  std::string log_;
  pid_t pid_{-1};
  bool reaped_{false};
};

}  // namespace rescue::test
