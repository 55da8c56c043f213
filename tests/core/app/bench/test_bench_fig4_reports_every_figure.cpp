// `rescue-motion bench fig4` (the paper's Fig. 4 experiment) runs a short smoke run to the end: it
// says what the machine gave (kernel, PREEMPT_RT or not, CPUs, the Table I mapping), prints the
// summary (min, mean, std, max, p99.9) of both tasks in both cases as `key: value unit` lines, with
// no heap allocation after init, and writes one CSV row per task, case and period; the handler's
// period is also reported split into the handler alone (the paper's Fig. 4 figure), the simulator's
// share and the wait for the frame, in the summary and the CSV, the three adding up to it. No timing is
// asserted (docs/timing.md holds a run's figures); the plot is skipped (--no-plot) to keep it short.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/support/run_command.hpp"

namespace rescue {
namespace {

const std::string kProgram = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

TEST(BenchFig4, ShortRunReportsBothTasksInBothCasesAndWritesTheSeries) {
  ASSERT_EQ(::access(kProgram.c_str(), X_OK), 0) << kProgram << " is not built";
  char dir[] = "/tmp/test-bench-fig4-XXXXXX";
  ASSERT_NE(::mkdtemp(dir), nullptr);
  const test::CommandOutput out = test::run_command("'" + kProgram + "' bench fig4 --periods 200 --no-plot --out " +
                                                    dir + " 2>&1");
  ASSERT_EQ(out.exit_status, 0) << out.out;
  for (const char* line : {"bench: fig4\n", "\nkernel: ", "\npreempt_rt: ", "\nprivileges: ", "\ncpus_online: ",
                           "\naffinity_mapping: EtherCAT handler: Table I CPU 3 -> CPU ", "\nload: stress,udp\n",
                           "\nperiods_per_case: 200 periods\n", "\nother_rt_threads_before_cpu0: ", "\nheap_allocations_after_init: 0 allocations\n"}) {
    EXPECT_NE(out.out.find(line), std::string::npos) << line << "\n" << out.out;
  }
  for (const char* task : {"ethercat", "rc"}) {
    for (const char* which : {"_without_affinity_", "_with_affinity_"}) {
      for (const char* figure : {"execution_min: ", "execution_mean: ", "execution_std: ", "execution_max: ",
                                 "execution_p99.9: ", "wakeup_latency_p99.9: "}) {
        const std::string key = std::string("\n") + task + which + figure;
        EXPECT_NE(out.out.find(key), std::string::npos) << key << "\n" << out.out;
      }
    }
  }
  for (const char* which : {"_without_affinity_", "_with_affinity_"}) {
    for (const char* part : {"handler_only", "simulator", "frame_wait"}) {
      for (const char* figure : {"_min: ", "_mean: ", "_std: ", "_max: ", "_p99.9: "}) {
        const std::string key = std::string("\nethercat") + which + part + figure;
        EXPECT_NE(out.out.find(key), std::string::npos) << key << "\n" << out.out;
      }
    }
  }
  std::ifstream csv(std::string(dir) + "/fig4.csv");
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  EXPECT_EQ(line, "case,task,period,execution_ns,latency_ns,handler_only_ns,simulator_ns,frame_wait_ns");
  int rows = 0;
  while (std::getline(csv, line)) {
    ++rows;
    // The handler's three parts add up to its period (within the ns each was rounded to); the RC
    // task has none.
    std::istringstream fields(line);
    std::string case_name;
    std::string task;
    std::string cell;
    long long v[6] = {};
    std::getline(fields, case_name, ',');
    std::getline(fields, task, ',');
    std::getline(fields, cell, ',');  // period
    for (long long& x : v) {
      std::getline(fields, cell, ',');
      x = std::atoll(cell.c_str());
    }
    const long long parts = v[2] + v[3] + v[4];
    if (task == "ethercat") {
      EXPECT_LE(std::llabs(parts - v[0]), 3) << line;
      EXPECT_GT(v[3], 0) << "the simulator processed a frame: " << line;
    } else {
      EXPECT_EQ(parts, 0) << line;
    }
  }
  EXPECT_EQ(rows, 4 * 200);
  EXPECT_EQ(std::system(("rm -rf '" + std::string(dir) + "'").c_str()), 0);
}

}  // namespace
}  // namespace rescue
