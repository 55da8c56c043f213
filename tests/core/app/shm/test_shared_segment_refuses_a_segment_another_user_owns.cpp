// The shared-memory segment and another user (docs/shared-memory.md "Protocol", docs/security.md):
// the attack is a local user who creates the segment's name first with a header naming a
// live pid (pid 1). Such a segment is refused as "owned by uid N, not ours", never taken for a
// running instance, never mapped and never unlinked; `run --segment NAME` says so and exits 1
// within 2 s. A segment this program creates has mode 0600. The other user is `nobody` (uid 65534):
// the test chowns the segment, which needs root; without it the test is skipped, saying why.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

#include "core/app/shm/shared_segment.hpp"
#include "hal/proc/process_identity.hpp"
#include "hal/shm/shared_memory.hpp"
#include "tests/support/run_command.hpp"

namespace rescue::app::shm {
namespace {

constexpr uid_t kNobody = 65534;

std::string name_for(const char* what) {
  return "/rescue-test-" + std::to_string(::getpid()) + "-" + what;
}

// What the attacker leaves at `name`: a header of this program's layout naming pid 1 (alive),
// owned by nobody.
bool plant_foreign_segment(const std::string& name) {
  (void)::shm_unlink(name.c_str());
  const int fd = ::shm_open(name.c_str(), O_CREAT | O_EXCL | O_RDWR, 0644);
  if (fd < 0 || ::ftruncate(fd, static_cast<off_t>(kSegmentSize)) != 0) return false;
  void* p = ::mmap(nullptr, kSegmentSize, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  if (p == MAP_FAILED) return false;
  const Result<std::uint64_t> init_start = hal::process_start_time(1);
  SegmentHeader header{};
  header.magic = kMagic;
  header.header_size = sizeof(SegmentHeader);
  header.layout_version = TaskLinks::kLayoutVersion;
  header.layout_hash = kLayoutHash;
  header.total_size = kSegmentSize;
  header.creator_pid = 1;
  header.creator_start_time = init_start.ok() ? init_start.value() : 0;
  std::memcpy(p, &header, offsetof(SegmentHeader, ready));
  (void)::munmap(p, kSegmentSize);
  const bool chowned = ::fchown(fd, kNobody, kNobody) == 0;
  (void)::close(fd);
  return chowned;
}

bool still_there(const std::string& name) {
  struct stat st {};
  return ::stat(("/dev/shm" + name).c_str(), &st) == 0 && st.st_uid == kNobody;
}

TEST(OtherUsersSegment, ASegmentThisProgramCreatesHasMode0600) {
  const std::string name = name_for("mode");
  (void)::shm_unlink(name.c_str());
  const mode_t old = ::umask(0);  // even with no umask
  Result<hal::SharedMemory> made = hal::SharedMemory::create_exclusive(name.c_str(), 4096);
  (void)::umask(old);
  ASSERT_TRUE(made.ok());
  struct stat st {};
  ASSERT_EQ(::stat(("/dev/shm" + name).c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 07777U, 0600U);
  EXPECT_EQ(st.st_uid, ::geteuid());
  EXPECT_TRUE(hal::SharedMemory::unlink(name.c_str()).ok());
}

TEST(OtherUsersSegment, ASegmentAnotherUserOwnsIsRefusedAsSuchNotTakenForARunningInstance) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to give a segment to nobody (uid 65534)";
  const std::string name = name_for("foreign");
  ASSERT_TRUE(plant_foreign_segment(name));
  const Result<SegmentName> segment = segment_name(name.c_str());
  ASSERT_TRUE(segment.ok());
  const Result<SegmentOwner> created = SegmentOwner::create(segment.value(), nullptr);
  ASSERT_FALSE(created.ok());
  EXPECT_EQ(created.error().code, Errc::permission_denied);
  EXPECT_EQ(created.error().detail0, kNobody);
  char line[512];
  (void)describe_segment_error(segment.value(), created.error(), line, sizeof line);
  EXPECT_NE(std::strstr(line, "owned by uid 65534, not ours"), nullptr) << line;
  EXPECT_EQ(std::strstr(line, "running process"), nullptr) << line;
  EXPECT_TRUE(still_there(name)) << "another user's segment was removed";
  // Attaching is refused the same way.
  EXPECT_EQ(hal::SharedMemory::open_existing(name.c_str()).error().code, Errc::permission_denied);
  (void)::shm_unlink(name.c_str());
}

TEST(OtherUsersSegment, RunRefusesASegmentAnotherUserOwnsWithinTwoSeconds) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to give a segment to nobody (uid 65534)";
  const std::string name = name_for("run");
  ASSERT_TRUE(plant_foreign_segment(name));
  char dir[] = "/tmp/rm-foreign-seg-XXXXXX";
  ASSERT_NE(::mkdtemp(dir), nullptr);
  const auto t0 = std::chrono::steady_clock::now();
  const test::CommandOutput out = test::run_command("timeout -s KILL 10 " + std::string(RESCUE_BINARY_DIR) +
                                                   "/rescue-motion run --state-dir " + dir + " --segment " + name +
                                                   " --duration 1 2>&1");
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(out.exit_status, 1) << out.out;
  EXPECT_LT(took, 2.0);
  EXPECT_NE(out.out.find("is owned by uid 65534, not ours"), std::string::npos) << out.out;
  EXPECT_EQ(out.out.find("in use by a running process"), std::string::npos) << out.out;
  EXPECT_TRUE(still_there(name));
  (void)::shm_unlink(name.c_str());
  (void)test::run_command(std::string("rm -rf ") + dir);
}

}  // namespace
}  // namespace rescue::app::shm
