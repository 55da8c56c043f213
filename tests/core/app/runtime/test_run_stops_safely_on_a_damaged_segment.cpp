// Issue 35 item 8: random bytes written over a live run's shared-memory segment (a stray write or
// a bit flip; docs/shared-memory.md "A damaged segment"). The supervisor says so once, kills every
// task (safe hold: no frame any more), exits with status 6 within seconds instead of draining a
// "queue" of 2^63 entries, and records no joint as lost. The same for one byte of the run's own
// record (RunControl's robot condition, a value no writer writes), which the supervisor checks on
// every pass (core/app/runtime/run_control_check.hpp).
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>

#include "core/app/shm/segment_layout.hpp"
#include "hal/shm/shared_memory.hpp"
#include "tests/support/background_run.hpp"
#include "tests/support/joint_manager_fakes.hpp"

namespace rescue::app {
namespace {

using std::chrono::milliseconds;

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(DamagedSegment, RandomBytesOverALiveSegmentStopTheRunOnceAndRecordNoLoss) {
  testing::TempStateDir dir;
  const std::string segment = "/rescue-test-damaged-" + std::to_string(::getpid());
  test::BackgroundRun run({"run", "--duration", "60", "--initialize", "--state-dir", dir.path, "--segment", segment},
                          dir.path + "/run.log");
  ASSERT_TRUE(run.wait_for("operator: initialize: accepted", milliseconds(30000))) << run.output();
  const std::string errors_file = dir.path + "/error-joints.bin";
  const bool had_file = ::access(errors_file.c_str(), F_OK) == 0;
  const std::string before = had_file ? test::read_text_file(errors_file) : std::string();
  {
    Result<hal::SharedMemory> shared = hal::SharedMemory::open_existing(segment.c_str());
    ASSERT_TRUE(shared.ok());
    std::mt19937_64 random(8);
    auto* bytes = static_cast<unsigned char*>(shared.value().data());
    for (std::size_t i = 0; i + sizeof(std::uint64_t) <= shared.value().size(); i += sizeof(std::uint64_t)) {
      const std::uint64_t word = random();
      std::memcpy(bytes + i, &word, sizeof word);
    }
  }
  const auto started = std::chrono::steady_clock::now();
  const int status = run.wait_exit();  // the test's own time limit ends a hang
  const auto took = std::chrono::duration_cast<milliseconds>(std::chrono::steady_clock::now() - started);
  const std::string out = run.output();
  EXPECT_EQ(status, 6) << out;
  EXPECT_LT(took.count(), 20000) << "not a hang";
  EXPECT_EQ(count_of(out, "shared segment " + segment + " damaged"), 1U) << out;
  EXPECT_EQ(count_of(out, "refused: "), 0U) << "no garbage replies drained";
  EXPECT_EQ(out.size() < 200000, true) << "no flood of output: " << out.size() << " bytes";
  // No joint recorded as lost: the error-joints file is as it was (or still absent).
  EXPECT_EQ(::access(errors_file.c_str(), F_OK) == 0, had_file);
  if (had_file) {
    EXPECT_EQ(test::read_text_file(errors_file), before);
  }
}

TEST(DamagedSegment, ADamagedByteOfTheRunsOwnRecordStopsTheRunOnceAndNamesIt) {
  testing::TempStateDir dir;
  const std::string segment = "/rescue-test-damaged-run-" + std::to_string(::getpid());
  test::BackgroundRun run({"run", "--duration", "60", "--initialize", "--state-dir", dir.path, "--segment", segment},
                          dir.path + "/run.log");
  ASSERT_TRUE(run.wait_for("operator: initialize: accepted", milliseconds(30000))) << run.output();
  {
    Result<hal::SharedMemory> shared = hal::SharedMemory::open_existing(segment.c_str());
    ASSERT_TRUE(shared.ok());
    auto* bytes = static_cast<unsigned char*>(shared.value().data());
    const std::size_t at = shm::kLinksOffset + offsetof(TaskLinks, run) + offsetof(RunControl, condition);
    ASSERT_LT(at, shared.value().size());
    bytes[at] = 0x7F;  // no RobotCondition
  }
  const auto started = std::chrono::steady_clock::now();
  const int status = run.wait_exit();
  const auto took = std::chrono::duration_cast<milliseconds>(std::chrono::steady_clock::now() - started);
  const std::string out = run.output();
  EXPECT_EQ(status, 6) << out;
  EXPECT_LT(took.count(), 20000) << "stopped at the supervisor's next pass, not at --duration";
  EXPECT_EQ(count_of(out, "shared segment " + segment + " damaged (RunControl::condition)"), 1U) << out;
}

}  // namespace
}  // namespace rescue::app
