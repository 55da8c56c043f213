// Issue 35, item 6: `decode` read the whole file into memory before the first byte was checked (a
// 2 GiB sparse file: 12 s and 2.1 GB before failing at byte 0). The reader now also streams: a
// CaptureSource read record by record into a window of the caller's. Streamed through the smallest
// window it gives exactly the frames (numbers, bytes, times, interfaces) the whole-file reader gives,
// for pcap and pcapng of many windows' size with sections and interfaces changing on the way; no read
// asks for more than the window; a pcapng block larger than the window is refused, not read in part;
// a file cut short reports the same truncation either way.
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

void expect_same_both_ways(const std::vector<std::uint8_t>& file, std::size_t expected_frames) {
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
  EXPECT_GT(file.size(), 4 * window.size()) << "the file spans several windows";
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
