// What CaptureWriter records comes back from CaptureReader byte for byte, with its nanosecond
// timestamp (plus the configured offset) and direction; oversized frames are cut to the snap
// length and counted; a full disk is counted per frame and never stops recording; the file stays
// readable after a failed write.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>

#include <cstdint>
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

TEST(CaptureWriter, FullDiskIsCountedPerFrameAndNeverStopsRecording) {
  if (::access("/dev/full", W_OK) != 0) GTEST_SKIP() << "/dev/full is not available";
  CaptureWriter w;
  const Status opened = w.open("/dev/full");
  // The header itself cannot be written: open says so and leaves the writer closed.
  ASSERT_FALSE(opened.ok());
  EXPECT_EQ(opened.error().code, Errc::io_error);
  EXPECT_STREQ(opened.error().what, "write capture header");
  EXPECT_EQ(opened.error().detail0, static_cast<std::uint32_t>(ENOSPC));
  EXPECT_FALSE(w.is_open());
  const auto f = frame_with(Command::BRD, 2);
  w.record(ConstByteSpan(f.data(), f.size()), 1, FrameDirection::outbound);  // closed: ignored
  EXPECT_EQ(w.stats().frames_written, 0U);
}

TEST(CaptureWriter, WriteFailuresAfterOpenAreCountedAndTheFileStaysReadable) {
  // A file size limit makes the kernel cut one write short and refuse the ones after it (EFBIG),
  // like a disk filling up during a run. SIGXFSZ is ignored so the failure arrives as errno.
  const std::string path = temp_path("writer-fail");
  const auto f = frame_with(Command::LRW, 100);
  CaptureWriter w;
  ASSERT_TRUE(w.open(path.c_str()).ok());
  w.record(ConstByteSpan(f.data(), f.size()), 1, FrameDirection::outbound);
  const std::uint64_t one_frame = w.stats().bytes_written;

  rlimit old_limit{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old_limit), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit small = old_limit;
  small.rlim_cur = static_cast<rlim_t>(one_frame + 50);  // the next block fits only partly
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  for (int cycle = 0; cycle < 1000; ++cycle) w.record(ConstByteSpan(f.data(), f.size()), cycle, FrameDirection::inbound);
  const CaptureWriterStats stats = w.stats();
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &old_limit), 0);
  (void)std::signal(SIGXFSZ, old_handler);

  EXPECT_EQ(stats.frames_written, 1U);
  EXPECT_EQ(stats.write_errors, 1000U);
  EXPECT_EQ(stats.last_errno, EFBIG);
  EXPECT_EQ(stats.bytes_written, one_frame);
  EXPECT_TRUE(w.close().ok());

  // The torn block was cut off again: the file holds exactly the header and the first frame.
  const auto file = read_file(path);
  EXPECT_EQ(file.size(), one_frame);
  EXPECT_EQ(test::read_all_frames(file).size(), 1U);
  ::unlink(path.c_str());
}

TEST(CaptureWriter, OpenErrors) {
  CaptureWriter w;
  const Status missing_dir = w.open("/nonexistent-dir/x.pcapng");
  ASSERT_FALSE(missing_dir.ok());
  EXPECT_EQ(missing_dir.error().code, Errc::io_error);
  EXPECT_STREQ(missing_dir.error().what, "open capture");
  EXPECT_EQ(missing_dir.error().detail0, static_cast<std::uint32_t>(ENOENT));

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
