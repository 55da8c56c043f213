// What CaptureWriter records comes back from CaptureReader byte for byte, with its nanosecond
// timestamp (plus the configured offset) and direction; oversized frames are cut to the snap
// length and counted; a full disk is counted per frame and never stops recording; the file stays
// readable after a failed write.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "ecat/capture/capture_reader.hpp"
#include "ecat/capture/capture_writer.hpp"
#include "ecat/codec/frame.hpp"
#include "tests/support/read_frames.hpp"

namespace rescue::ecat {
namespace {

std::string temp_path(const char* name) {
  return std::string(::testing::TempDir()) + "/" + name + "-" + std::to_string(::getpid()) + ".pcapng";
}

std::vector<std::uint8_t> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::vector<std::uint8_t> frame_with(Command command, std::uint16_t length) {
  FrameBuilder b;
  b.reset(MacAddress{0x02, 0, 0, 0, 0, 0x01});
  EXPECT_TRUE(b.add(command, 7, make_address(0x1000, 0x0910), length).ok());
  const ConstByteSpan f = b.finish();
  return std::vector<std::uint8_t>(f.begin(), f.end());
}

TEST(CaptureWriter, FramesTimestampsAndDirectionsReadBack) {
  const std::string path = temp_path("writer-roundtrip");
  const hal::Nanoseconds offset = 1'700'000'000'000'000'000LL;  // 2023-11-14, as wall-clock time
  std::vector<std::vector<std::uint8_t>> sent;
  {
    CaptureWriter w;
    ASSERT_TRUE(w.open(path.c_str(), CaptureWriterOptions{"sim0", offset}).ok());
    EXPECT_TRUE(w.is_open());
    for (std::uint8_t raw = 0; raw < kCommandCount; ++raw) {
      sent.push_back(frame_with(static_cast<Command>(raw), static_cast<std::uint16_t>(raw * 10)));
      const auto& f = sent.back();
      w.record(ConstByteSpan(f.data(), f.size()), 1'000'000LL * raw + 1, raw % 2 == 0 ? FrameDirection::outbound : FrameDirection::inbound);
    }
    sent.push_back(frame_with(Command::LRW, static_cast<std::uint16_t>(kMaxDatagramDataLength)));
    w.record(ConstByteSpan(sent.back().data(), sent.back().size()), 999, FrameDirection::unknown);
    EXPECT_EQ(w.stats().frames_written, sent.size());
    EXPECT_EQ(w.stats().write_errors, 0U);
    EXPECT_EQ(w.stats().frames_truncated, 0U);
    EXPECT_TRUE(w.close().ok());
    EXPECT_FALSE(w.is_open());
  }
  const auto file = read_file(path);
  const auto frames = test::read_all_frames(file);
  ASSERT_EQ(frames.size(), sent.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(frames[i].number, i + 1);
    ASSERT_EQ(frames[i].bytes.size(), sent[i].size());
    EXPECT_TRUE(std::equal(sent[i].begin(), sent[i].end(), frames[i].bytes.begin()));
    EXPECT_EQ(frames[i].original_length, sent[i].size());
    EXPECT_EQ(frames[i].link_type, capture::kLinkTypeEthernet);
    if (i < kCommandCount) {
      EXPECT_EQ(frames[i].timestamp_ns, static_cast<std::uint64_t>(offset + 1'000'000LL * static_cast<hal::Nanoseconds>(i) + 1));
      EXPECT_EQ(frames[i].direction, i % 2 == 0 ? FrameDirection::outbound : FrameDirection::inbound);
    }
  }
  EXPECT_EQ(frames.back().direction, FrameDirection::unknown);
  ::unlink(path.c_str());
}

TEST(CaptureWriter, FramesLongerThanTheSnapLengthAreCutAndCounted) {
  const std::string path = temp_path("writer-snap");
  std::vector<std::uint8_t> jumbo(3000, 0xAB);
  {
    CaptureWriter w;
    ASSERT_TRUE(w.open(path.c_str()).ok());
    w.record(ConstByteSpan(jumbo.data(), jumbo.size()), 5, FrameDirection::inbound);
    EXPECT_EQ(w.stats().frames_truncated, 1U);
    EXPECT_EQ(w.stats().frames_written, 1U);
  }
  const auto file = read_file(path);
  const auto frames = test::read_all_frames(file);
  ASSERT_EQ(frames.size(), 1U);
  EXPECT_EQ(frames[0].bytes.size(), CaptureWriter::kSnapLength);
  EXPECT_EQ(frames[0].original_length, 3000U);
  ::unlink(path.c_str());
}

TEST(CaptureWriter, TimestampsBeforeTheEpochAreWrittenAsZero) {
  const std::string path = temp_path("writer-negative");
  const auto f = frame_with(Command::BRD, 2);
  {
    CaptureWriter w;
    ASSERT_TRUE(w.open(path.c_str(), CaptureWriterOptions{"x", -100}).ok());
    w.record(ConstByteSpan(f.data(), f.size()), 50, FrameDirection::outbound);
  }
  const auto frames = test::read_all_frames(read_file(path));
  ASSERT_EQ(frames.size(), 1U);
  EXPECT_EQ(frames[0].timestamp_ns, 0U);
  ::unlink(path.c_str());
}

// A file system that refuses the writes (here RLIMIT_FSIZE 0 in a child: every write fails with
// EFBIG, as a full disk fails with ENOSPC): open says the header could not be written and leaves the
// writer closed. (A device such as /dev/full is no capture file at all: refused before writing.)
TEST(CaptureWriter, FullDiskIsCountedPerFrameAndNeverStopsRecording) {
  const std::string path = temp_path("writer-full");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    (void)::signal(SIGXFSZ, SIG_IGN);
    const rlimit none{0, 0};
    if (::setrlimit(RLIMIT_FSIZE, &none) != 0) ::_exit(10);
    CaptureWriter w;
    const Status opened = w.open(path.c_str());
    if (opened.ok() || w.is_open()) ::_exit(11);
    if (opened.error().code != Errc::io_error || std::strcmp(opened.error().what, "write capture header") != 0) ::_exit(12);
    if (opened.error().detail0 != static_cast<std::uint32_t>(EFBIG)) ::_exit(13);
    const auto f = frame_with(Command::BRD, 2);
    w.record(ConstByteSpan(f.data(), f.size()), 1, FrameDirection::outbound);  // closed: ignored
    ::_exit(w.stats().frames_written == 0 ? 0 : 14);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "child check " << WEXITSTATUS(status) << " failed";
  ::unlink(path.c_str());
  CaptureWriter device;
  const Status refused = device.open("/dev/full");
  ASSERT_FALSE(refused.ok());
  EXPECT_STREQ(refused.error().what, "not a regular file");
  EXPECT_NE(std::string(device.problem().c_str()).find("character device"), std::string::npos) << device.problem().c_str();
}

TEST(CaptureWriter, OpenErrors) {
  CaptureWriter w;
  const Status missing_dir = w.open("/nonexistent-dir/x.pcapng");
  ASSERT_FALSE(missing_dir.ok());
  EXPECT_EQ(missing_dir.error().code, Errc::not_found);
  EXPECT_EQ(missing_dir.error().detail0, static_cast<std::uint32_t>(ENOENT));
  EXPECT_NE(std::string(w.problem().c_str()).find("/nonexistent-dir/x.pcapng"), std::string::npos) << w.problem().c_str();

  const std::string long_name(CaptureWriter::kMaxInterfaceNameLength + 1, 'n');
  const Status too_long = w.open(temp_path("writer-name").c_str(), CaptureWriterOptions{long_name.c_str(), 0});
  ASSERT_FALSE(too_long.ok());
  EXPECT_EQ(too_long.error().code, Errc::invalid_argument);

  const std::string path = temp_path("writer-twice");
  ASSERT_TRUE(w.open(path.c_str()).ok());
  const Status twice = w.open(path.c_str());
  ASSERT_FALSE(twice.ok());
  EXPECT_STREQ(twice.error().what, "already open");
  EXPECT_TRUE(w.close().ok());
  EXPECT_TRUE(w.close().ok());  // closing a closed writer is fine
  ::unlink(path.c_str());
}

TEST(CaptureWriter, UnixTimeOffsetMapsClockTimeToNow) {
  hal::VirtualClock clock(42);
  const hal::Nanoseconds offset = unix_time_offset(clock);
  // 42 ns on the virtual clock is "now" in Unix time: after 2020 and before 2100.
  EXPECT_GT(offset + 42, 1'577'836'800LL * hal::kNsPerSec);
  EXPECT_LT(offset + 42, 4'102'444'800LL * hal::kNsPerSec);
}

}  // namespace
}  // namespace rescue::ecat
