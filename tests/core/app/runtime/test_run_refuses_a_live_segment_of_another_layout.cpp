// Issue 12: a segment at the run's name (`run --segment NAME`) whose creator still runs and whose
// header has another layout version, or the same version and another layout hash (another build),
// makes `rescue-motion run` exit non-zero before anything starts, with one message naming both
// versions and hashes, the creator's pid and what to do; the segment is left exactly as it was (every
// byte) and still exists. This test process is the live creator (core/app/shm/shared_segment.hpp).
#include <gtest/gtest.h>

#include <unistd.h>

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

}  // namespace
}  // namespace rescue::app
