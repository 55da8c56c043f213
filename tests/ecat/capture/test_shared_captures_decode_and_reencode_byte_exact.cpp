// Every frame of the real captures in ../shared/vectors/captures (TwinCAT, SOEM and a DC master
// talking to real slaves) is read by CaptureReader and decodes with FrameView; building the frame
// again with FrameBuilder from the decoded fields gives back the same bytes: Ethernet header,
// EtherCAT header and every datagram. Only Ethernet padding may differ in presence: captures taken
// on the sending host show frames before the NIC pads them to 60 bytes.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "ecat/capture/capture_reader.hpp"
#include "ecat/codec/frame.hpp"
#include "tests/support/shared_captures.hpp"

namespace rescue::ecat {
namespace {

const std::string& kCaptures = test::kSharedCaptureDir;

struct Expected {
  const char* file;
  std::size_t frames;       // packet records in the file
  std::size_t ethercat;     // of which EtherCAT
  std::size_t datagrams;
};

// Frame and datagram counts as tshark reports them for these files.
const Expected kFiles[] = {
    {"twincat-run-ek1100-el1004.pcapng", 554, 553, 581},
    {"soem-single-lan9252.pcapng", 999, 998, 998},
    {"soem-sdinfo-akd.pcapng", 6762, 6759, 6759},
    {"replay-dc.pcapng", 3604, 3604, 5676},
};

class SharedCapture : public testing::TestWithParam<Expected> {
 protected:
  void SetUp() override {
    path_ = kCaptures + GetParam().file;
    if (::access(path_.c_str(), R_OK) != 0) {
      GTEST_SKIP() << "no shared captures: " << kCaptures << " is absent (the data is not part of the repository)";
    }
    std::ifstream in(path_, std::ios::binary);
    bytes_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  std::string path_;
  std::vector<std::uint8_t> bytes_;
};

TEST_P(SharedCapture, EveryFrameDecodesAndReencodesToTheSameBytes) {
  auto reader = CaptureReader::open(ConstByteSpan(bytes_.data(), bytes_.size()));
  ASSERT_TRUE(reader.ok()) << reader.error().what;
  std::size_t frames = 0;
  std::size_t ethercat = 0;
  std::size_t datagrams = 0;
  std::size_t padded = 0;
  CapturedFrame captured;
  for (;;) {
    const Result<bool> more = reader.value().next(captured);
    ASSERT_TRUE(more.ok()) << more.error().what << " at byte " << more.error().detail1;
    if (!more.value()) break;
    ++frames;
    ASSERT_EQ(captured.link_type, capture::kLinkTypeEthernet);
    ASSERT_EQ(captured.bytes.size(), captured.original_length) << "frame " << captured.number << " was cut";
    const auto parsed = FrameView::parse(captured.bytes);
    if (!parsed.ok()) {
      ASSERT_STREQ(parsed.error().what, "not EtherCAT") << "frame " << captured.number << " offset " << parsed.error().detail1;
      continue;
    }
    ++ethercat;
    const FrameHeader& h = parsed.value().header();
    ASSERT_FALSE(h.vlan_tagged);

    FrameBuilder b;
    b.reset(h.source, h.destination);
    for (const DatagramView d : parsed.value()) {
      ASSERT_FALSE(d.circulating()) << "frame " << captured.number;
      const auto slot = b.add(d.command(), d.index(), d.address(), d.length(), d.data(), d.irq(), d.wkc());
      ASSERT_TRUE(slot.ok()) << "frame " << captured.number << ": " << slot.error().what;
      ++datagrams;
    }
    const ConstByteSpan rebuilt = b.finish();
    const std::size_t end = h.ecat_end();
    ASSERT_TRUE(std::equal(rebuilt.begin(), rebuilt.begin() + static_cast<std::ptrdiff_t>(end), captured.bytes.begin()))
        << "frame " << captured.number << " differs";
    // Padding: absent (captured before the NIC), or present up to 60 bytes and zero like ours.
    ASSERT_TRUE(captured.bytes.size() == end || captured.bytes.size() == rebuilt.size())
        << "frame " << captured.number << ": " << captured.bytes.size() << " bytes, EtherCAT ends at " << end;
    if (captured.bytes.size() > end) {
      ++padded;
      EXPECT_TRUE(std::equal(rebuilt.begin() + static_cast<std::ptrdiff_t>(end), rebuilt.end(),
                             captured.bytes.begin() + static_cast<std::ptrdiff_t>(end)));
    }
  }
  EXPECT_EQ(frames, GetParam().frames);
  EXPECT_EQ(ethercat, GetParam().ethercat);
  EXPECT_EQ(datagrams, GetParam().datagrams);
  RecordProperty("padded_frames", static_cast<int>(padded));
}

TEST_P(SharedCapture, TimestampsAreInCaptureOrder) {
  auto reader = CaptureReader::open(ConstByteSpan(bytes_.data(), bytes_.size()));
  ASSERT_TRUE(reader.ok());
  CapturedFrame f;
  std::uint64_t last = 0;
  // All four files were captured between 2022 and 2026.
  while (reader.value().next(f).value_or(false)) {
    EXPECT_GE(f.timestamp_ns, last) << "frame " << f.number;
    EXPECT_GT(f.timestamp_ns, 1'640'995'200ULL * 1'000'000'000ULL);
    EXPECT_LT(f.timestamp_ns, 1'798'761'600ULL * 1'000'000'000ULL);
    last = f.timestamp_ns;
  }
  EXPECT_EQ(reader.value().frames_read(), GetParam().frames);
}

INSTANTIATE_TEST_SUITE_P(Captures, SharedCapture, testing::ValuesIn(kFiles),
                         [](const testing::TestParamInfo<Expected>& p) { return test::capture_test_name(p.param.file); });

}  // namespace
}  // namespace rescue::ecat
