// Issue 12: a segment at the run's name (`run --segment NAME`) whose creator still runs and whose
// header has another layout version, or the same version and another layout hash (another build),
// makes `rescue-motion run` exit non-zero before anything starts, with one message naming both
// versions and hashes, the creator's pid and what to do; the segment is left exactly as it was (every
// byte) and still exists. This test process is the live creator (core/app/shm/shared_segment.hpp).
// And a task process that attaches by name to a segment of another layout refuses it (last test).
#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "core/app/shm/shared_segment.hpp"
#include "hal/shm/shared_memory.hpp"
#include "tests/support/background_run.hpp"
#include "tests/support/joint_manager_fakes.hpp"

namespace rescue::app {
namespace {

std::string hex(std::uint32_t v) {
  char text[16];
  (void)std::snprintf(text, sizeof text, "0x%08" PRIx32, v);
  return text;
}

std::vector<std::uint8_t> bytes_of(const std::string& segment) {
  const Result<hal::SharedMemory> memory = hal::SharedMemory::open_existing(segment.c_str());
  if (!memory.ok()) return {};
  const auto* data = static_cast<const std::uint8_t*>(memory.value().data());
  return std::vector<std::uint8_t>(data, data + memory.value().size());
}

// A live segment at `segment` whose header says `version` and `hash`; `run` against it.
void expect_refused(const char* what, std::uint32_t version, std::uint32_t hash) {
  testing::TempStateDir dir;
  const std::string segment = "/rescue-test-foreign-" + std::string(what) + "-" + std::to_string(::getpid());
  (void)hal::SharedMemory::unlink(segment.c_str());
  const Result<shm::SegmentName> name = shm::segment_name(segment.c_str());
  ASSERT_TRUE(name.ok());
  Result<shm::SegmentOwner> foreign = shm::SegmentOwner::create(name.value(), nullptr);
  ASSERT_TRUE(foreign.ok());
  foreign.value().segment().header.layout_version = version;
  foreign.value().segment().header.layout_hash = hash;
  const std::vector<std::uint8_t> before = bytes_of(segment);
  ASSERT_FALSE(before.empty());

  test::BackgroundRun run({"run", "--duration", "2", "--state-dir", dir.path, "--segment", segment},
                          dir.path + "/run.log");
  const int status = run.wait_exit();
  const std::string out = run.output();
  EXPECT_NE(status, 0) << out;
  const std::string expected = "rescue-motion run: segment " + segment + ": layout version " + std::to_string(version) +
                               " hash " + hex(hash) + " of running pid " + std::to_string(::getpid()) +
                               ", this program has version " + std::to_string(TaskLinks::kLayoutVersion) + " hash " +
                               hex(shm::kLayoutHash) +
                               "; refused, left as it is (stop that program or use another --segment); not starting\n";
  EXPECT_NE(out.find(expected), std::string::npos) << out;
  EXPECT_EQ(out.find("bringing the EtherCAT network up"), std::string::npos) << out;
  EXPECT_EQ(out.find("supervisor: started"), std::string::npos) << out;
  EXPECT_TRUE(bytes_of(segment) == before) << "the refused run changed the segment";
  std::printf("%s: %s", what, out.c_str());
}

TEST(ForeignSegment, ALiveSegmentOfAnotherLayoutVersionIsRefusedAndLeftUntouched) {
  expect_refused("version", TaskLinks::kLayoutVersion + 1, shm::kLayoutHash ^ 0x5a5aU);
}

TEST(ForeignSegment, ALiveSegmentOfTheSameVersionAndAnotherHashIsRefusedAndLeftUntouched) {
  expect_refused("hash", TaskLinks::kLayoutVersion, shm::kLayoutHash ^ 0xffU);
}

// A task process attaches to the segment by its name after its fork (docs/shared-memory.md "Attach").
// While a run is in OP, this test process unlinks the run's name and puts a segment of another layout
// version there (it stays its live creator), then SIGKILLs the message parser: every restarted
// message parser refuses that segment with the message naming both versions and exits 5 without running; the
// EtherCAT handler, still on the run's own (unnamed) segment, keeps cycling with no healthy joint
// missing a cycle; SIGTERM stops the run with exit 0, and the run leaves the segment now at its name
// exactly as it was (the supervisor unlinks its name only while it still names its own segment).
TEST(ForeignSegment, ARestartedTaskProcessRefusesASegmentOfAnotherLayoutAtItsName) {
  testing::TempStateDir dir;
  const std::string segment = "/rescue-test-foreign-task-" + std::to_string(::getpid());
  (void)hal::SharedMemory::unlink(segment.c_str());
  test::BackgroundRun run({"run", "--duration", "60", "--initialize", "--state-dir", dir.path, "--segment", segment},
                          dir.path + "/run.log");
  ASSERT_TRUE(run.wait_for("operator: initialize: accepted", std::chrono::milliseconds(30000))) << run.output();
  const pid_t parser = run.pid_on_line("supervisor: started message-parser");
  ASSERT_GT(parser, 0) << run.output();

  ASSERT_EQ(hal::SharedMemory::unlink(segment.c_str()).ok(), true);
  const Result<shm::SegmentName> name = shm::segment_name(segment.c_str());
  ASSERT_TRUE(name.ok());
  Result<shm::SegmentOwner> foreign = shm::SegmentOwner::create(name.value(), nullptr);
  ASSERT_TRUE(foreign.ok());
  foreign.value().segment().header.layout_version = TaskLinks::kLayoutVersion + 1;
  const std::vector<std::uint8_t> before = bytes_of(segment);
  ASSERT_EQ(::kill(parser, SIGKILL), 0);
  const std::string refusal = "rescue-motion run: message-parser: segment " + segment + ": layout version " +
                              std::to_string(TaskLinks::kLayoutVersion + 1) + " found, this program has " +
                              std::to_string(TaskLinks::kLayoutVersion) + "; refused";
  EXPECT_TRUE(run.wait_for(refusal, std::chrono::milliseconds(5000))) << run.output();
  EXPECT_TRUE(run.wait_for("supervisor: message-parser (pid", std::chrono::milliseconds(1000))) << run.output();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ASSERT_EQ(::kill(run.pid(), SIGTERM), 0);
  const int status = run.wait_exit();
  const std::string out = run.output();
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(out.find("exit status 5"), std::string::npos) << out;  // the refusing message parser's
  EXPECT_NE(out.find("healthy joints missed 0 cycles"), std::string::npos) << out;
  EXPECT_NE(out.find("ethercat-handler restarts: 0\n"), std::string::npos) << out;
  EXPECT_TRUE(bytes_of(segment) == before) << "the run changed or removed the segment at its name";
  std::printf("%s\n", refusal.c_str());
}

}  // namespace
}  // namespace rescue::app
