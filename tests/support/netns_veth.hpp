// Test support: a veth pair between two network namespaces that the test creates and always
// removes, so raw-socket tests exchange real frames through the kernel without touching the host's
// interfaces. Names are unique per process and per pair, so parallel test runs never clash.
//
//   namespace <base>-m            namespace <base>-s
//   ecm0 (the master's end) <---> ecs0 (the slaves' end)
//
// Creating namespaces needs root (CAP_SYS_ADMIN and CAP_NET_ADMIN). Without it the fixture skips
// the test saying why, except when CI=true, where these tests must run and the fixture fails.
#pragma once

#include <fcntl.h>
#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <utility>

#include <gtest/gtest.h>

namespace rescue::testing {

// Runs `command` through the shell; returns its exit status and puts stdout+stderr into `output`.
inline int run_shell(const std::string& command, std::string& output) {
  output.clear();
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return -1;
  std::array<char, 256> chunk{};
  while (std::fgets(chunk.data(), static_cast<int>(chunk.size()), pipe) != nullptr) output += chunk.data();
  const int status = ::pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class VethPair {
 public:
  static constexpr const char* kMasterInterface = "ecm0";
  static constexpr const char* kSlaveInterface = "ecs0";

  // The pair, or nullptr with the reason in `why`.
  static std::unique_ptr<VethPair> create(std::string& why) {
    if (::geteuid() != 0) {
      why = "not root: cannot create network namespaces (run the netns tests as root: `sudo ctest -L netns`)";
      return nullptr;
    }
    std::string output;
    if (run_shell("command -v ip", output) != 0) {
      why = "iproute2 (`ip`) not installed: cannot create the veth pair (toolchain/setup.sh installs it)";
      return nullptr;
    }
    static int counter = 0;
    const std::string base = "rmtest-" + std::to_string(::getpid()) + "-" + std::to_string(++counter);
    std::unique_ptr<VethPair> pair(new VethPair(base + "-m", base + "-s"));
    const std::string m = pair->master_ns_;
    const std::string s = pair->slave_ns_;
    const std::string script = "set -e; ip netns add " + m + "; ip netns add " + s + "; ip link add name " +
                               kMasterInterface + " netns " + m + " type veth peer name " + kSlaveInterface +
                               " netns " + s + "; ip -n " + m + " link set " + kMasterInterface + " up; ip -n " +
                               s + " link set " + kSlaveInterface + " up";
    if (run_shell(script, output) != 0) {
      why = "cannot create network namespaces and veth pair: " + output;
      return nullptr;  // the destructor removes whatever part was created
    }
    return pair;
  }

  ~VethPair() {
    std::string ignored;
    // Deleting a namespace destroys the veth end inside it, and with it the peer.
    (void)run_shell("ip netns del " + master_ns_ + "; ip netns del " + slave_ns_, ignored);
  }
  VethPair(const VethPair&) = delete;
  VethPair& operator=(const VethPair&) = delete;

  const std::string& master_ns() const { return master_ns_; }
  const std::string& slave_ns() const { return slave_ns_; }

  // `ip -n NS COMMAND`: e.g. link_command(slave_ns(), "link set ecs0 down").
  static bool ip(const std::string& ns, const std::string& command, std::string& output) {
    return run_shell("ip -n " + ns + " " + command, output) == 0;
  }

 private:
  VethPair(std::string m, std::string s) : master_ns_(std::move(m)), slave_ns_(std::move(s)) {}
  std::string master_ns_;
  std::string slave_ns_;
};

// Moves the calling thread into a named network namespace until destroyed. Sockets opened meanwhile
// stay in that namespace for their whole life, so one test process can hold both ends of the pair.
class InNamespace {
 public:
  explicit InNamespace(const std::string& ns) {
    original_ = ::open("/proc/self/ns/net", O_RDONLY | O_CLOEXEC);
    const int target = ::open(("/run/netns/" + ns).c_str(), O_RDONLY | O_CLOEXEC);
    entered_ = original_ >= 0 && target >= 0 && ::setns(target, CLONE_NEWNET) == 0;
    if (target >= 0) ::close(target);
  }
  ~InNamespace() {
    if (entered_) (void)::setns(original_, CLONE_NEWNET);
    if (original_ >= 0) ::close(original_);
  }
  InNamespace(const InNamespace&) = delete;
  InNamespace& operator=(const InNamespace&) = delete;
  bool entered() const { return entered_; }

 private:
  int original_{-1};
  bool entered_{false};
};

// Fixture: every test gets its own pair (fresh interfaces, empty queues).
class NetnsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why;
    veth_ = VethPair::create(why);
    if (veth_) return;
    const char* ci = std::getenv("CI");
    if (ci != nullptr && std::strcmp(ci, "true") == 0) {
      FAIL() << "CI must run the netns tests but " << why;
    } else {
      GTEST_SKIP() << why;
    }
  }
  void TearDown() override { veth_.reset(); }

  std::unique_ptr<VethPair> veth_;
};

}  // namespace rescue::testing
