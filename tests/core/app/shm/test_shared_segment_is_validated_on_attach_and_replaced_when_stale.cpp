// The shared-memory segment's protocol (core/app/shm/shared_segment.hpp, docs/shared-memory.md):
// a process attaches to what another created (across fork), waits bounded for the ready word,
// refuses another layout version or hash naming both values, and a segment whose creator was
// killed is replaced, never trusted.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <string>

#include "core/app/shm/shared_segment.hpp"
#include "hal/shm/shared_memory.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app::shm {
namespace {

SegmentName test_name(const char* what) {
  char text[64];
  (void)std::snprintf(text, sizeof text, "/rescue-test-%d-%s", static_cast<int>(::getpid()), what);
  const Result<SegmentName> name = segment_name(text);
  EXPECT_TRUE(name.ok());
  (void)hal::SharedMemory::unlink(text);  // a leftover of an earlier crashed test run
  return name.value();
}

std::string describe(const SegmentName& name, const Error& error) {
  char line[256];
  (void)describe_segment_error(name, error, line, sizeof line);
  return line;
}

TEST(SharedSegment, ChildAttachesBeforeCreationWaitsAndSeesTheSameMemory) {
  const SegmentName name = test_name("fork");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    hal::MonotonicClock clock;
    Result<SegmentAttachment> attached = SegmentAttachment::attach(name, clock, 5 * hal::kNsPerSec);
    if (!attached.ok()) ::_exit(2);
    if (attached.value().segment().header.creator_pid != static_cast<std::int32_t>(::getppid())) ::_exit(3);
    attached.value().links().rc_heartbeat_ns[1].store(1234, std::memory_order_release);
    ::_exit(0);
  }
  hal::MonotonicClock clock;
  clock.sleep_until(clock.now() + 20 * hal::kNsPerMs);  // the child is already waiting
  CreateReport report;
  Result<SegmentOwner> owner = SegmentOwner::create(name, &report);
  ASSERT_TRUE(owner.ok()) << describe(name, owner.error());
  EXPECT_EQ(report.previous, Previous::none);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_EQ(owner.value().links().rc_heartbeat_ns[1].load(std::memory_order_acquire), 1234);
  const SegmentHeader& header = owner.value().segment().header;
  EXPECT_EQ(header.magic, kMagic);
  EXPECT_EQ(header.layout_version, TaskLinks::kLayoutVersion);
  EXPECT_EQ(header.layout_hash, kLayoutHash);
  EXPECT_EQ(header.total_size, kSegmentSize);
  EXPECT_EQ(header.ready.load(), kReady);
}

TEST(SharedSegment, OwnerUnlinksTheNameWhenItGoes) {
  const SegmentName name = test_name("unlink");
  {
    Result<SegmentOwner> owner = SegmentOwner::create(name, nullptr);
    ASSERT_TRUE(owner.ok());
  }
  EXPECT_EQ(hal::SharedMemory::open_existing(name.c_str()).error().code, Errc::not_found);
}

TEST(SharedSegment, AnotherLayoutVersionIsRefusedNamingBoth) {
  const SegmentName name = test_name("version");
  Result<SegmentOwner> owner = SegmentOwner::create(name, nullptr);
  ASSERT_TRUE(owner.ok());
  owner.value().segment().header.layout_version = TaskLinks::kLayoutVersion + 1;
  hal::VirtualClock clock;
  const Result<SegmentAttachment> attached = SegmentAttachment::attach(name, clock, hal::kNsPerSec);
  ASSERT_FALSE(attached.ok());
  EXPECT_EQ(attached.error().code, Errc::version);
  EXPECT_EQ(attached.error().detail0, TaskLinks::kLayoutVersion + 1);
  EXPECT_EQ(attached.error().detail1, TaskLinks::kLayoutVersion);
  const std::string line = describe(name, attached.error());
  EXPECT_NE(line.find("layout version " + std::to_string(TaskLinks::kLayoutVersion + 1) + " found"), std::string::npos) << line;
  EXPECT_NE(line.find("this program has " + std::to_string(TaskLinks::kLayoutVersion)), std::string::npos) << line;
}

TEST(SharedSegment, AnotherLayoutHashIsRefusedNamingBoth) {
  const SegmentName name = test_name("hash");
  Result<SegmentOwner> owner = SegmentOwner::create(name, nullptr);
  ASSERT_TRUE(owner.ok());
  owner.value().segment().header.layout_hash = kLayoutHash ^ 0xffU;
  hal::VirtualClock clock;
  const Result<SegmentAttachment> attached = SegmentAttachment::attach(name, clock, hal::kNsPerSec);
  ASSERT_FALSE(attached.ok());
  EXPECT_EQ(attached.error().code, Errc::mismatch);
  EXPECT_EQ(attached.error().detail0, kLayoutHash ^ 0xffU);
  EXPECT_EQ(attached.error().detail1, kLayoutHash);
  char expected[64];
  (void)std::snprintf(expected, sizeof expected, "this program has 0x%08x", static_cast<unsigned>(kLayoutHash));
  const std::string line = describe(name, attached.error());
  EXPECT_NE(line.find(expected), std::string::npos) << line;
  EXPECT_NE(line.find("layout hash 0x"), std::string::npos) << line;
}

TEST(SharedSegment, AttachBeforeReadyWaitsThenTimesOutWithAClearError) {
  const SegmentName name = test_name("ready");
  // The name exists and is sized, but nobody constructs it: the ready word stays 0.
  Result<hal::SharedMemory> raw = hal::SharedMemory::create_exclusive(name.c_str(), kSegmentSize);
  ASSERT_TRUE(raw.ok());
  hal::VirtualClock clock(1000);
  const Result<SegmentAttachment> attached = SegmentAttachment::attach(name, clock, 50 * hal::kNsPerMs);
  ASSERT_FALSE(attached.ok());
  EXPECT_EQ(attached.error().code, Errc::timeout);
  EXPECT_EQ(attached.error().detail0, 1U);  // it exists
  EXPECT_GE(clock.now(), 1000 + 50 * hal::kNsPerMs);  // it waited the whole bound
  EXPECT_LE(clock.now(), 1000 + 52 * hal::kNsPerMs);  // and no longer
  EXPECT_NE(describe(name, attached.error()).find("ready word is not set"), std::string::npos);
  (void)hal::SharedMemory::unlink(name.c_str());
  // No segment at all: the same bound, another reason.
  const Result<SegmentAttachment> none = SegmentAttachment::attach(name, clock, 10 * hal::kNsPerMs);
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.error().code, Errc::timeout);
  EXPECT_EQ(none.error().detail0, 0U);
}

TEST(SharedSegment, ASegmentOfAKilledCreatorIsReplacedNotTrusted) {
  const SegmentName name = test_name("stale");
  int ready_pipe[2];
  ASSERT_EQ(::pipe(ready_pipe), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    Result<SegmentOwner> owner = SegmentOwner::create(name, nullptr);
    if (!owner.ok()) ::_exit(2);
    owner.value().links().rc_heartbeat_ns[0].store(42);
    const char byte = 1;
    (void)::write(ready_pipe[1], &byte, 1);
    for (;;) ::pause();  // killed here: the name is never unlinked
  }
  char byte = 0;
  ASSERT_EQ(::read(ready_pipe[0], &byte, 1), 1);
  ASSERT_EQ(::kill(child, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  (void)::close(ready_pipe[0]);
  (void)::close(ready_pipe[1]);

  CreateReport report;
  Result<SegmentOwner> owner = SegmentOwner::create(name, &report);
  ASSERT_TRUE(owner.ok()) << describe(name, owner.error());
  EXPECT_EQ(report.previous, Previous::creator_dead);
  EXPECT_EQ(report.previous_creator.pid, static_cast<std::int32_t>(child));
  EXPECT_EQ(owner.value().links().rc_heartbeat_ns[0].load(), 0);  // fresh, nothing of the dead run
  EXPECT_EQ(owner.value().segment().header.creator_pid, static_cast<std::int32_t>(::getpid()));
}

TEST(SharedSegment, ASegmentWithoutAHeaderIsReplaced) {
  const SegmentName name = test_name("garbage");
  Result<hal::SharedMemory> raw = hal::SharedMemory::create_exclusive(name.c_str(), 16);
  ASSERT_TRUE(raw.ok());
  CreateReport report;
  const Result<SegmentOwner> owner = SegmentOwner::create(name, &report);
  ASSERT_TRUE(owner.ok());
  EXPECT_EQ(report.previous, Previous::no_header);
}

TEST(SharedSegment, ASegmentOfALiveCreatorIsNotReplaced) {
  const SegmentName name = test_name("live");
  const Result<SegmentOwner> first = SegmentOwner::create(name, nullptr);
  ASSERT_TRUE(first.ok());
  const Result<SegmentOwner> second = SegmentOwner::create(name, nullptr);
  ASSERT_FALSE(second.ok());
  EXPECT_EQ(second.error().code, Errc::busy);
  EXPECT_EQ(second.error().detail0, static_cast<std::uint32_t>(::getpid()));
  EXPECT_NE(describe(name, second.error()).find("in use by a running process"), std::string::npos);
}

TEST(SharedSegment, ALiveSegmentOfAnotherLayoutIsRefusedNamingBothAndLeftAsItIs) {
  const SegmentName name = test_name("live-other");
  Result<SegmentOwner> first = SegmentOwner::create(name, nullptr);
  ASSERT_TRUE(first.ok());
  first.value().segment().header.layout_version = TaskLinks::kLayoutVersion + 1;
  first.value().segment().header.layout_hash = 0x12345678U;
  const Result<SegmentOwner> second = SegmentOwner::create(name, nullptr);
  ASSERT_FALSE(second.ok());
  EXPECT_EQ(second.error().code, Errc::version);
  EXPECT_EQ(second.error().detail0, TaskLinks::kLayoutVersion + 1);
  EXPECT_EQ(second.error().detail1, 0x12345678U);
  const std::string line = describe(name, second.error());
  EXPECT_NE(line.find("layout version " + std::to_string(TaskLinks::kLayoutVersion + 1) + " hash 0x12345678 of running pid " +
                      std::to_string(::getpid()) + ", this program has version " + std::to_string(TaskLinks::kLayoutVersion)),
            std::string::npos)
      << line;
  EXPECT_NE(line.find("use another --segment"), std::string::npos) << line;
  // The first one's segment is still the one at the name, untouched.
  EXPECT_EQ(first.value().segment().header.layout_hash, 0x12345678U);
  EXPECT_EQ(first.value().segment().header.ready.load(), kReady);
  EXPECT_TRUE(hal::SharedMemory::open_existing(name.c_str()).ok());
}

TEST(SharedSegment, DefaultNameFollowsTheStateDirectoryAndBadNamesAreRefused) {
  const SegmentName a = default_segment_name("/var/lib/rescue-motion");
  const SegmentName b = default_segment_name("/tmp/other");
  EXPECT_EQ(std::string(a.c_str()).rfind("/rescue-motion-", 0), 0U);
  EXPECT_NE(std::string(a.c_str()), std::string(b.c_str()));
  EXPECT_EQ(std::string(a.c_str()), std::string(default_segment_name("/var/lib/rescue-motion").c_str()));
  EXPECT_TRUE(hal::valid_shared_memory_name(a.c_str()));
  EXPECT_FALSE(segment_name("no-slash").ok());
  EXPECT_FALSE(segment_name("/a/b").ok());
  EXPECT_FALSE(segment_name("/").ok());
  EXPECT_TRUE(segment_name("/rescue-arm-left").ok());
}

TEST(SharedSegment, LayoutTableCoversTaskLinksAndTheHashIsStable) {
  std::size_t end = kLinksOffset;
  for (const LayoutEntry& e : kLayout) {
    EXPECT_GE(e.offset, end) << e.name;  // in order, no overlap
    end = e.offset + e.size;
  }
  EXPECT_LE(end, kSegmentSize);
  EXPECT_GE(end + alignof(TaskLinks), kSegmentSize);  // only tail padding after the last member
  static_assert(kLayoutHash != 0, "computed at compile time");
}

}  // namespace
}  // namespace rescue::app::shm
