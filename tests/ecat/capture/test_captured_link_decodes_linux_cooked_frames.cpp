// A Linux cooked capture (SLL, link type 113, what `tcpdump -i any` writes; SLL2, 276, `tshark -i
// any`) holds EtherCAT frames behind a cooked header instead of an Ethernet one. decode_captured_frame
// finds them (EtherType 0x88A4, optionally behind one 802.1Q tag), checks every header length, skips
// other EtherTypes as "not EtherCAT" and refuses other link types. Every frame of the shared real
// captures, re-wrapped in SLL and SLL2, decodes to the same datagrams as the Ethernet original.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "ecat/capture/capture_reader.hpp"
#include "ecat/capture/captured_link.hpp"
#include "ecat/codec/frame.hpp"
#include "tests/support/shared_captures.hpp"

namespace rescue::ecat {
namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes ethernet_frame() {
  FrameBuilder b;
  b.reset(MacAddress{0x02, 0, 0, 0, 0, 0x01});
  EXPECT_TRUE(b.add(Command::FPRD, 7, make_address(0x1001, 0x0130), 2, {}, 0, 1).ok());
  EXPECT_TRUE(b.add(Command::LRW, 8, 0x00010000, 4, {}, 0, 3).ok());
  const ConstByteSpan f = b.finish();
  return Bytes(f.begin(), f.end());
}

// Appends the frame's bytes after its 14-byte Ethernet header. Element by element: GCC 12 at -O3
// inlines vector::insert of an iterator range here into a false -Warray-bounds (README command 1's
// release build failed on it).
void append_after_ethernet_header(Bytes& p, const Bytes& ethernet) {
  for (std::size_t i = 14; i < ethernet.size(); ++i) p.push_back(ethernet[i]);
}

// The SLL header (16 bytes) for `protocol`, then the frame's bytes after its Ethernet header.
Bytes sll(const Bytes& ethernet, std::uint16_t protocol = kEtherTypeEtherCAT) {
  Bytes p{0x00, 0x04, 0x00, 0x01, 0x00, 0x06, 0x02, 0, 0, 0, 0, 0x01, 0, 0};
  p.push_back(static_cast<std::uint8_t>(protocol >> 8));
  p.push_back(static_cast<std::uint8_t>(protocol & 0xFF));
  append_after_ethernet_header(p, ethernet);
  return p;
}

Bytes sll2(const Bytes& ethernet, std::uint16_t protocol = kEtherTypeEtherCAT) {
  Bytes p{static_cast<std::uint8_t>(protocol >> 8), static_cast<std::uint8_t>(protocol & 0xFF), 0, 0, 0, 0, 0, 3,
          0x00, 0x01, 0x04, 0x06, 0x02, 0, 0, 0, 0, 0x01, 0, 0};
  append_after_ethernet_header(p, ethernet);
  return p;
}

struct Line {
  Command command;
  std::uint8_t index;
  std::uint32_t address;
  std::uint16_t length;
  std::uint16_t wkc;
  bool operator==(const Line& o) const {
    return command == o.command && index == o.index && address == o.address && length == o.length && wkc == o.wkc;
  }
};

std::vector<Line> lines(const FrameView& v) {
  std::vector<Line> out;
  for (const DatagramView d : v) out.push_back({d.command(), d.index(), d.address(), d.length(), d.wkc()});
  return out;
}

std::vector<Line> decode(std::uint16_t link_type, const Bytes& p) {
  const auto r = decode_captured_frame(link_type, ConstByteSpan(p.data(), p.size()));
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().what);
  return r.ok() ? lines(r.value()) : std::vector<Line>{};
}

Error decode_error(std::uint16_t link_type, const Bytes& p) {
  const auto r = decode_captured_frame(link_type, ConstByteSpan(p.data(), p.size()));
  EXPECT_FALSE(r.ok());
  return r.ok() ? Error{} : r.error();
}

TEST(CapturedLink, SllAndSll2GiveTheDatagramsOfTheEthernetFrame) {
  const Bytes eth = ethernet_frame();
  const std::vector<Line> expected = decode(capture::kLinkTypeEthernet, eth);
  ASSERT_EQ(expected.size(), 2U);
  EXPECT_EQ(decode(capture::kLinkTypeLinuxSll, sll(eth)), expected);
  EXPECT_EQ(decode(capture::kLinkTypeLinuxSll2, sll2(eth)), expected);
}

TEST(CapturedLink, CookedVlanTagIsSkipped) {
  const Bytes eth = ethernet_frame();
  Bytes tagged = sll(eth, kEtherTypeVlan);
  const Bytes tag{0x00, 0x05, 0x88, 0xA4};
  tagged.insert(tagged.begin() + 16, tag.begin(), tag.end());
  EXPECT_EQ(decode(capture::kLinkTypeLinuxSll, tagged), decode(capture::kLinkTypeEthernet, eth));
  tagged.resize(16 + 3);  // tag cut short
  EXPECT_STREQ(decode_error(capture::kLinkTypeLinuxSll, tagged).what, "sll vlan tag");
}

TEST(CapturedLink, OtherProtocolsAreNotEtherCAT) {
  const Bytes eth = ethernet_frame();
  const Error e1 = decode_error(capture::kLinkTypeLinuxSll, sll(eth, 0x0800));
  EXPECT_EQ(e1.code, Errc::unsupported);
  EXPECT_STREQ(e1.what, "not EtherCAT");
  EXPECT_STREQ(decode_error(capture::kLinkTypeLinuxSll2, sll2(eth, 0x86DD)).what, "not EtherCAT");
}

TEST(CapturedLink, EveryCutOfACookedPacketIsAnErrorNeverAnOverread) {
  const Bytes eth = ethernet_frame();
  for (const std::uint16_t link : {capture::kLinkTypeLinuxSll, capture::kLinkTypeLinuxSll2}) {
    const Bytes full = link == capture::kLinkTypeLinuxSll ? sll(eth) : sll2(eth);
    const std::size_t header = link == capture::kLinkTypeLinuxSll ? capture::kSllHeaderSize : capture::kSll2HeaderSize;
    const std::size_t ecat_end = header + 2 + (2 + 12) + (4 + 12);
    for (std::size_t n = 0; n < ecat_end; ++n) {
      // An exactly-sized heap block: ASan sees any read past the cut.
      const Bytes cut(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(n));
      const Error e = decode_error(link, cut);
      EXPECT_TRUE(e.code == Errc::truncated) << "link " << link << " cut at " << n << ": " << e.what;
      if (n < header) {
        EXPECT_STREQ(e.what, "sll header");
      }
    }
  }
}

TEST(CapturedLink, PaddingAndGarbageFollowTheEthernetRules) {
  Bytes eth = ethernet_frame();
  store_le16(eth.data() + 14, static_cast<std::uint16_t>(load_le16(eth.data() + 14) + 1));  // one zero byte more
  Bytes p = sll2(eth);
  const auto r = decode_captured_frame(capture::kLinkTypeLinuxSll2, ConstByteSpan(p.data(), p.size()));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().header().padding, 1U);
  p[20 + 2 + 14 + 16] = 0x33;  // the padding byte is not zero: garbage
  EXPECT_STREQ(decode_error(capture::kLinkTypeLinuxSll2, p).what, "bytes after last datagram");
}

TEST(CapturedLink, OtherLinkTypesAreRefusedByNumber) {
  EXPECT_TRUE(is_supported_link_type(1));
  EXPECT_TRUE(is_supported_link_type(113));
  EXPECT_TRUE(is_supported_link_type(276));
  for (const std::uint16_t link : {0, 101, 105, 127, 228}) {
    EXPECT_FALSE(is_supported_link_type(link));
    const Error e = decode_error(link, ethernet_frame());
    EXPECT_EQ(e.code, Errc::unsupported);
    EXPECT_STREQ(e.what, "link type");
    EXPECT_EQ(e.detail1, link);
  }
}

class SharedCaptureRewrapped : public testing::TestWithParam<const char*> {};

TEST_P(SharedCaptureRewrapped, SllAndSll2DecodeLikeTheEthernetOriginal) {
  const std::string path = test::kSharedCaptureDir + GetParam();
  if (::access(path.c_str(), R_OK) != 0) GTEST_SKIP() << path << " is absent (data outside the repository)";
  std::ifstream in(path, std::ios::binary);
  const Bytes file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto reader = CaptureReader::open(ConstByteSpan(file.data(), file.size()));
  ASSERT_TRUE(reader.ok());
  CapturedFrame frame;
  std::size_t compared = 0;
  for (;;) {
    const auto more = reader.value().next(frame);
    ASSERT_TRUE(more.ok());
    if (!more.value()) break;
    const Bytes eth(frame.bytes.begin(), frame.bytes.end());
    const auto original = FrameView::parse(frame.bytes);
    if (!original.ok() || original.value().header().vlan_tagged) continue;
    const std::vector<Line> expected = lines(original.value());
    EXPECT_EQ(decode(capture::kLinkTypeLinuxSll, sll(eth)), expected) << "frame " << frame.number;
    EXPECT_EQ(decode(capture::kLinkTypeLinuxSll2, sll2(eth)), expected) << "frame " << frame.number;
    ++compared;
  }
  EXPECT_GT(compared, 100U);
}

INSTANTIATE_TEST_SUITE_P(Captures, SharedCaptureRewrapped, testing::ValuesIn(test::kSharedCaptures),
                         test::capture_param_name);

}  // namespace
}  // namespace rescue::ecat
