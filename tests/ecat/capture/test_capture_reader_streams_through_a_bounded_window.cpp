// Issue 35, item 6: `decode` read the whole file into memory before the first byte was checked (a
// 2 GiB sparse file: 12 s and 2.1 GB before failing at byte 0). The reader now also streams: a
// CaptureSource read record by record into a window of the caller's. Streamed through the smallest
// window it gives exactly the frames (numbers, bytes, times, interfaces) the whole-file reader gives,
// for pcap and pcapng of many windows' size with sections and interfaces changing on the way; no read
// asks for more than the window; a pcapng block larger than the window is refused, not read in part;
// a file cut short reports the same truncation either way, also where a block larger than the window
// runs past its end (a fuzz finding).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "ecat/capture/capture_reader.hpp"
#include "tests/support/capture_bytes.hpp"

namespace rescue::ecat {
namespace {

// The file's bytes served by offset, as pread serves them; counts what it was asked for.
class MemorySource final : public CaptureSource {
 public:
  explicit MemorySource(const std::vector<std::uint8_t>& bytes) : bytes_(bytes) {}
  Result<std::size_t> read_at(std::size_t offset, ByteSpan out) noexcept override {
    largest_request = std::max(largest_request, out.size());
    ++reads;
    if (offset >= bytes_.size()) return std::size_t{0};
    const std::size_t n = std::min(out.size(), bytes_.size() - offset);
    std::memcpy(out.data(), bytes_.data() + offset, n);
    return n;
  }
  std::size_t largest_request{0};
  std::size_t reads{0};

 private:
  const std::vector<std::uint8_t>& bytes_;
};

struct Seen {
  std::uint32_t number;
  std::vector<std::uint8_t> bytes;
  std::uint64_t timestamp_ns;
  std::uint16_t link_type;
  std::uint32_t interface_id;
  bool operator==(const Seen& o) const {
    return number == o.number && bytes == o.bytes && timestamp_ns == o.timestamp_ns && link_type == o.link_type &&
           interface_id == o.interface_id;
  }
};

// Every frame, then the error that ended the walk (Errc::ok at a clean end).
std::vector<Seen> walk(Result<CaptureReader> reader, Error& ended) {
  std::vector<Seen> seen;
  ended = Error{};
  if (!reader.ok()) {
    ended = reader.error();
    return seen;
  }
  CapturedFrame f;
  for (;;) {
    const Result<bool> more = reader.value().next(f);
    if (!more.ok()) {
      ended = more.error();
      return seen;
    }
    if (!more.value()) return seen;
    seen.push_back(Seen{f.number, std::vector<std::uint8_t>(f.bytes.begin(), f.bytes.end()), f.timestamp_ns, f.link_type,
                        f.interface_id});
  }
}

std::vector<std::uint8_t> frame_of(std::size_t n, std::size_t size) {
  std::vector<std::uint8_t> f(size);
  for (std::size_t i = 0; i < size; ++i) f[i] = static_cast<std::uint8_t>(n * 31 + i);
  return f;
}

// The frames and the end of both readers, compared; the end returned.
Error expect_same_end_both_ways(const std::vector<std::uint8_t>& file, std::size_t expected_frames) {
  Error whole_end;
  const std::vector<Seen> whole = walk(CaptureReader::open(ConstByteSpan(file.data(), file.size())), whole_end);
  std::vector<std::uint8_t> window(CaptureReader::kMinWindow);
  MemorySource source(file);
  Error streamed_end;
  const std::vector<Seen> streamed = walk(CaptureReader::open(source, ByteSpan(window.data(), window.size())), streamed_end);
  EXPECT_EQ(whole.size(), expected_frames);
  EXPECT_TRUE(streamed == whole) << streamed.size() << " streamed, " << whole.size() << " whole";
  EXPECT_EQ(streamed_end.code, whole_end.code);
  EXPECT_STREQ(streamed_end.what, whole_end.what);
  EXPECT_EQ(streamed_end.detail0, whole_end.detail0);
  EXPECT_EQ(streamed_end.detail1, whole_end.detail1);
  EXPECT_LE(source.largest_request, window.size());
  return whole_end;
}

void expect_same_both_ways(const std::vector<std::uint8_t>& file, std::size_t expected_frames) {
  (void)expect_same_end_both_ways(file, expected_frames);
  EXPECT_GT(file.size(), 4 * CaptureReader::kMinWindow) << "the file spans several windows";
}

TEST(StreamedCapture, PcapngOfManyWindowsGivesTheFramesOfTheWholeFileReader) {
  test::PcapngBuilder ng;
  ng.interface();
  std::size_t frames = 0;
  for (std::size_t i = 0; i < 4000; ++i) {
    if (i == 1500) ng.section(true).interface(capture::kLinkTypeEthernet, 0, 9).interface();  // big-endian, ns
    ng.packet(i >= 1500 ? static_cast<std::uint32_t>(i % 2) : 0, 1000 * i, frame_of(i, 60 + (i * 37) % 1400));
    ++frames;
  }
  ng.packet(0, 1, frame_of(1, 200000));  // a large one, near the window's size
  ++frames;
  expect_same_both_ways(ng.bytes(), frames);
  // Cut short inside the last block: the same truncation either way.
  std::vector<std::uint8_t> cut = ng.bytes();
  cut.resize(cut.size() - 100);
  expect_same_both_ways(cut, frames - 1);
}

TEST(StreamedCapture, PcapOfManyWindowsGivesTheFramesOfTheWholeFileReader) {
  for (const bool big_endian : {false, true}) {
    test::PcapBuilder pcap(big_endian, true);
    for (std::size_t i = 0; i < 5000; ++i) pcap.record(static_cast<std::uint32_t>(i), 7, frame_of(i, 60 + (i * 53) % 1500));
    pcap.record(1, 2, frame_of(2, capture::kMaxPacketLength));  // the largest record allowed
    expect_same_both_ways(pcap.bytes(), 5001);
    std::vector<std::uint8_t> cut = pcap.bytes();
    cut.resize(cut.size() - 10);
    expect_same_both_ways(cut, 5000);
  }
}

TEST(StreamedCapture, ABlockLargerThanTheWindowIsRefusedNotReadInPart) {
  test::PcapngBuilder ng;
  ng.interface().packet(0, 1, frame_of(0, 100));
  std::vector<std::uint8_t> body(CaptureReader::kMinWindow, 0);  // an unknown block type, skipped when whole
  ng.block(0x0BADBAD0, body);
  ng.packet(0, 2, frame_of(1, 100));
  std::vector<std::uint8_t> window(CaptureReader::kMinWindow);
  MemorySource source(ng.bytes());
  Error ended;
  const std::vector<Seen> seen = walk(CaptureReader::open(source, ByteSpan(window.data(), window.size())), ended);
  EXPECT_EQ(seen.size(), 1U);
  EXPECT_EQ(ended.code, Errc::capacity_exceeded);
  EXPECT_STREQ(ended.what, "block length");
  // The whole-file reader skips it: the refusal is the window's, and says so.
  Error whole_end;
  EXPECT_EQ(walk(CaptureReader::open(ConstByteSpan(ng.bytes().data(), ng.bytes().size())), whole_end).size(), 2U);
  EXPECT_EQ(whole_end.code, Errc::ok);
}

// Found by fuzz_capture_reader: a section header (section length 0xffffffffffffffc9, advisory) whose
// block length, 0x0032001c, is larger than the window and runs past the end of the 147-byte file. The
// whole-file reader said truncated, the streamed one capacity_exceeded; both now say truncated there.
TEST(StreamedCapture, ABlockLargerThanTheWindowPastTheEndOfTheFileIsATruncationEitherWay) {
  const std::vector<std::uint8_t> fuzz_finding = {
      0x0a, 0x0d, 0x0d, 0x0a, 0x1c, 0x00, 0x32, 0x00, 0x4d, 0x3c, 0x2b, 0x1a, 0x01, 0x00, 0x00, 0x00,
      0xc9, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x1c, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00,
      0x14, 0x00, 0x00, 0x00, 0x71, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x14, 0x00, 0x00, 0x00,
      0x06, 0x00, 0x00, 0x00, 0x60, 0xf8, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x4e, 0x3c, 0xb2,
      0xa1, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x3e, 0x00, 0x00, 0x00, 0x3e, 0x00, 0x00, 0x00,
      0x00, 0x04, 0x00, 0x01, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
      0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x60, 0x00,
      0x00, 0x00, 0x06, 0x00, 0x00, 0x00, 0x60, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x60,
      0x00, 0x00, 0x00,
  };
  ASSERT_EQ(fuzz_finding.size(), 147U);
  const Error end = expect_same_end_both_ways(fuzz_finding, 0);
  EXPECT_EQ(end.code, Errc::truncated);
  EXPECT_STREQ(end.what, "block length");
  EXPECT_EQ(end.detail1, 4U);
  // The same later in a file, after a packet: a block larger than the window, cut short.
  test::PcapngBuilder ng;
  ng.interface().packet(0, 1, frame_of(0, 100));
  const std::size_t block_at = ng.bytes().size();
  ng.block(0x0BADBAD0, std::vector<std::uint8_t>(CaptureReader::kMinWindow, 0));
  std::vector<std::uint8_t> cut = ng.bytes();
  cut.resize(block_at + 64);
  const Error later = expect_same_end_both_ways(cut, 1);
  EXPECT_EQ(later.code, Errc::truncated);
  EXPECT_EQ(later.detail1, block_at + 4);
}

TEST(StreamedCapture, AWindowSmallerThanTheLargestRecordIsRefused) {
  std::vector<std::uint8_t> none;
  MemorySource source(none);
  std::vector<std::uint8_t> window(CaptureReader::kMinWindow - 1);
  const Result<CaptureReader> r = CaptureReader::open(source, ByteSpan(window.data(), window.size()));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, Errc::invalid_argument);
}

}  // namespace
}  // namespace rescue::ecat
