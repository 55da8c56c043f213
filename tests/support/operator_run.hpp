// The operator's path as a user runs it (docs/operator.md): a real `rescue-motion run --listen
// 127.0.0.1 --key FILE` on the in-process simulator in a child process, and `rescue-motion ctl` verbs
// as separate processes. Ports are free UDP ports of 127.0.0.1 found per test (bound to port 0, then
// released), so parallel CTest runs do not collide.
#pragma once

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/joint_manager_fakes.hpp"

namespace rescue::app::testing {

inline const std::string& rescue_binary() {
  static const std::string path = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";
  return path;
}

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The first line of a file (of /proc: a task's comm or stat); empty when unreadable.
inline std::string first_line(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

// A UDP port of 127.0.0.1 that was free a moment ago (0 on failure).
inline std::uint16_t free_udp_port() {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) return 0;
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof a;
  std::uint16_t port = 0;
  if (::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0 &&
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) == 0) {
    port = ntohs(a.sin_port);
  }
  (void)::close(fd);
  return port;
}

struct CommandResult {
  int status{-1};  // exit status, or -signal
  std::string out;  // stdout and stderr together
};

// Runs `rescue-motion ARGS...` to its end; `with_stderr` false: stdout alone (a --json answer).
inline CommandResult run_program(const std::vector<std::string>& args, bool with_stderr = true) {
  std::string line = "'" + rescue_binary() + "'";
  for (const std::string& a : args) line += " '" + a + "'";
  line += with_stderr ? " 2>&1" : " 2>/dev/null";
  CommandResult r;
  FILE* p = ::popen(line.c_str(), "r");
  if (p == nullptr) return r;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, p)) > 0) r.out.append(buffer, n);
  const int status = ::pclose(p);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  return r;
}

// `rescue-motion run` on the simulator with the operator ports on 127.0.0.1, a fresh key made by
// `ctl keygen` (its output kept in `keygen`), stopped by SIGTERM in stop() (or by its --duration);
// `scenario` (optional) is passed as --scenario NAME, `extra` after it (e.g. --ring-nic sim).
class OperatorRun {
 public:
  explicit OperatorRun(const char* duration = "60", const char* scenario = nullptr, const std::vector<std::string>& extra = {}) {
    control_port = free_udp_port();
    sensor_port = free_udp_port();
    while (sensor_port == control_port) sensor_port = free_udp_port();
    key = dir.path + "/operator.key";
    log = dir.path + "/run.log";
    keygen = run_program({"ctl", "keygen", "--key", key});
    const std::string control = std::to_string(control_port);
    const std::string sensor = std::to_string(sensor_port);
    pid_ = ::fork();
    if (pid_ == 0) {
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
      (void)::dup2(fd, 1);
      (void)::dup2(fd, 2);
      std::vector<const char*> argv{rescue_binary().c_str(), "run", "--state-dir", dir.path.c_str(), "--key", key.c_str(),
                                    "--listen", "127.0.0.1", "--control-port", control.c_str(), "--sensor-port",
                                    sensor.c_str(), "--duration", duration};
      if (scenario != nullptr) argv.insert(argv.end(), {"--scenario", scenario});
      for (const std::string& e : extra) argv.push_back(e.c_str());
      argv.push_back(nullptr);
      ::execv(rescue_binary().c_str(), const_cast<char* const*>(argv.data()));
      ::_exit(127);
    }
  }
  OperatorRun(const OperatorRun&) = delete;
  OperatorRun& operator=(const OperatorRun&) = delete;
  ~OperatorRun() { (void)stop(); }

  // Waits (up to 30 s: a loaded host is slow to reach OP) until the log shows `text`.
  bool wait_for(const std::string& text) const {
    for (int i = 0; i < 3000; ++i) {
      if (read_text(log).find(text) != std::string::npos) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }
  // `rescue-motion ctl --key KEY --port CONTROL ARGS...`
  CommandResult ctl(std::vector<std::string> args) const {
    args.insert(args.begin(), {"ctl", "--key", key, "--port", std::to_string(control_port)});
    return run_program(args);
  }
  // SIGTERM, then the exit status (once; later calls return it again).
  int stop() {
    if (pid_ > 0) {
      (void)::kill(pid_, SIGTERM);
      int status = 0;
      (void)::waitpid(pid_, &status, 0);
      exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
      pid_ = -1;
    }
    return exit_status_;
  }
  std::string output() const { return read_text(log); }
  // The run's EtherCAT handler got SCHED_FIFO (the run prints "ethercat: running degraded" when the
  // kernel refused it, e.g. without CAP_SYS_NICE or in a cgroup without real-time runtime).
  bool handler_got_sched_fifo() const { return output().find("ethercat: running degraded") == std::string::npos; }
  // The run's pid (the supervisor: the task processes are its children); -1 once stopped.
  pid_t pid() const { return pid_; }

  TempStateDir dir;
  std::uint16_t control_port{0};
  std::uint16_t sensor_port{0};
  std::string key;
  std::string log;
  CommandResult keygen;

 private:
  pid_t pid_{-1};
  int exit_status_{-1};
};

// The raw value of "key": in one flat JSON object of `ctl --json` (strings without their quotes;
// empty when absent).
inline std::string json_field(const std::string& object, const std::string& key) {
  const std::size_t at = object.find("\"" + key + "\":");
  if (at == std::string::npos) return "";
  std::size_t from = at + key.size() + 3;
  if (from < object.size() && object[from] == '"') {
    ++from;
    return object.substr(from, object.find('"', from) - from);
  }
  return object.substr(from, object.find_first_of(",}", from) - from);
}

// The object of joint `joint` in `ctl --json status` (empty when absent).
inline std::string joint_object(const std::string& json, const std::string& joint) {
  const std::size_t at = json.find("{\"name\":\"" + joint + "\"");
  if (at == std::string::npos) return "";
  return json.substr(at, json.find('}', at) - at + 1);
}

}  // namespace rescue::app::testing
