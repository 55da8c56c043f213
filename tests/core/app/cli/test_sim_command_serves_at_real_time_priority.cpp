// `rescue-motion sim --iface` stands for hardware: it must answer within microseconds even on a
// busy host, or a master's single-shot reads time out (SOEM's ec_configdc then takes a stale port
// receive time and computes wrong propagation delays). So it serves at SCHED_FIFO priority 90 by
// default, reports each real-time item, and --priority 0 leaves normal scheduling. It serves on the
// EtherCAT task's CPU by default (where a real NIC's interrupt goes: a master pinned at real-time
// priority otherwise had the kernel wake it on the other CPU, docs/hal.md), --cpu any leaves it to the
// scheduler, and a CPU the machine does not have is an error.
#include <sched.h>
#include <unistd.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/app/config/task_table.hpp"
#include "core/base/sanitizers.hpp"
#include "tests/support/child_process.hpp"
#include "tests/support/netns_veth.hpp"

namespace rescue::app {
namespace {

using rescue::testing::ChildProcess;
using rescue::testing::VethPair;

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";
constexpr int kStartTimeoutMs = 10000;

struct Scheduling {
  int policy{-1};
  int rt_priority{-1};
};

// Fields 40 (rt_priority) and 41 (policy) of /proc/PID/stat; the command name (field 2) is in
// parentheses and contains no spaces here.
Scheduling scheduling_of(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  std::getline(stat, line);
  std::istringstream fields(line.substr(line.rfind(')') + 2));
  std::vector<std::string> rest;  // from field 3 on
  std::string f;
  while (fields >> f) rest.push_back(f);
  Scheduling s;
  if (rest.size() >= 39) {
    s.rt_priority = std::stoi(rest[37]);
    s.policy = std::stoi(rest[38]);
  }
  return s;
}

// The CPUs `pid` may run on.
std::vector<int> cpus_of(pid_t pid) {
  cpu_set_t set;
  CPU_ZERO(&set);
  std::vector<int> cpus;
  if (::sched_getaffinity(pid, sizeof set, &set) != 0) return cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c) {
    if (CPU_ISSET(c, &set)) cpus.push_back(c);
  }
  return cpus;
}

class SimCommandScheduling : public rescue::testing::NetnsTest {
 protected:
  void start(const std::vector<std::string>& extra) {
    std::vector<std::string> argv{kBinary, "sim", "--iface", VethPair::kSlaveInterface};
    argv.insert(argv.end(), extra.begin(), extra.end());
    ASSERT_TRUE(sim_.start(argv, veth_->slave_ns()));
    ASSERT_TRUE(sim_.wait_for_output("serving 23 slaves on", kStartTimeoutMs)) << sim_.output();
  }
  ChildProcess sim_;
};

TEST_F(SimCommandScheduling, ServesAtFifoPriority90ByDefaultAndSaysSo) {
  start({});
  const Scheduling s = scheduling_of(sim_.pid());
  if (kSanitizerSpinsBySchedYield) {  // refused with its reason (docs/build.md): normal scheduling
    EXPECT_EQ(s.policy, SCHED_OTHER) << sim_.output();
    EXPECT_NE(sim_.output().find("rt: SCHED_FIFO priority 90: refused (unsupported: "), std::string::npos) << sim_.output();
    return;
  }
  EXPECT_EQ(s.policy, SCHED_FIFO) << sim_.output();
  EXPECT_EQ(s.rt_priority, 90);
  EXPECT_NE(sim_.output().find("rt: SCHED_FIFO priority 90: applied"), std::string::npos) << sim_.output();
  EXPECT_NE(sim_.output().find("rt: memory lock (mlockall current+future): "), std::string::npos) << sim_.output();
}

TEST_F(SimCommandScheduling, PriorityZeroKeepsNormalScheduling) {
  start({"--priority", "0"});
  const Scheduling s = scheduling_of(sim_.pid());
  EXPECT_EQ(s.policy, SCHED_OTHER);
  EXPECT_NE(sim_.output().find("rt: SCHED_FIFO priority: skipped"), std::string::npos) << sim_.output();
}

TEST_F(SimCommandScheduling, ServesOnTheEthercatTasksCpuByDefault) {
  start({});
  const int ethercat_cpu = table_cpu_on_this_machine(task_spec(TaskId::ethercat_handler).cpu);
  EXPECT_EQ(cpus_of(sim_.pid()), std::vector<int>{ethercat_cpu}) << sim_.output();
  EXPECT_NE(sim_.output().find("rt: CPU affinity " + std::to_string(ethercat_cpu) + ": applied"), std::string::npos) << sim_.output();
}

TEST_F(SimCommandScheduling, CpuAnyLeavesItToTheScheduler) {
  start({"--cpu", "any"});
  EXPECT_EQ(cpus_of(sim_.pid()).size(), static_cast<std::size_t>(::sysconf(_SC_NPROCESSORS_ONLN))) << sim_.output();
  EXPECT_NE(sim_.output().find("rt: CPU affinity: skipped"), std::string::npos) << sim_.output();
}

TEST_F(SimCommandScheduling, CpuZeroIsTaken) {
  start({"--cpu", "0"});
  EXPECT_EQ(cpus_of(sim_.pid()), std::vector<int>{0}) << sim_.output();
}

TEST(SimCommandCpu, ACpuTheMachineDoesNotHaveIsAnError) {
  ChildProcess sim;
  ASSERT_TRUE(sim.start({kBinary, "sim", "--iface", "lo", "--cpu", std::to_string(::sysconf(_SC_NPROCESSORS_ONLN))}));
  EXPECT_EQ(sim.wait_exit(), 1);
  EXPECT_NE(sim.output().find("--cpu must be `any` or a CPU of this machine"), std::string::npos) << sim.output();
}

TEST(SimCommandPriority, OutOfRangeIsAnError) {
  ChildProcess sim;
  ASSERT_TRUE(sim.start({kBinary, "sim", "--iface", "lo", "--priority", "100"}));
  EXPECT_EQ(sim.wait_exit(), 1);
  EXPECT_NE(sim.output().find("--priority must be 0..99"), std::string::npos) << sim.output();
}

}  // namespace
}  // namespace rescue::app
