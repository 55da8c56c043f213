// Cutting a frame at any byte gives an error value, never a read past the cut. Each cut is copied
// into a heap block of exactly that size, so the AddressSanitizer build (asan preset) turns any
// out-of-bounds read into a failure. Two ways to cut:
//  - the capture cut the frame: the EtherCAT header still announces the full length;
//  - the EtherCAT length itself is cut: the datagram walk must notice (header, data or wkc cut).
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "ecat/codec/frame.hpp"

namespace rescue::ecat {
namespace {

struct Sample {
  const char* name;
  std::vector<std::uint8_t> bytes;
};

std::vector<std::uint8_t> finish_copy(FrameBuilder& b) {
  const ConstByteSpan f = b.finish();
  return std::vector<std::uint8_t>(f.begin(), f.end());
}

std::vector<Sample> samples() {
  std::vector<Sample> out;
  {
    FrameBuilder b;
    EXPECT_TRUE(b.add(Command::BRD, 0, 0, 2).ok());
    out.push_back({"one datagram", finish_copy(b)});
  }
  {
    FrameBuilder b;
    EXPECT_TRUE(b.add(Command::FRMW, 1, make_address(0x1000, 0x0910), 8).ok());
    EXPECT_TRUE(b.add(Command::LRW, 2, 0, 100).ok());
    EXPECT_TRUE(b.add(Command::NOP, 3, 0, 0).ok());
    EXPECT_TRUE(b.add(Command::FPRD, 4, make_address(0x1001, 0x0130), 2).ok());
    out.push_back({"four datagrams", finish_copy(b)});
  }
  {
    FrameBuilder b;
    EXPECT_TRUE(b.add(Command::LRD, 0, 0, static_cast<std::uint16_t>(kMaxDatagramDataLength)).ok());
    out.push_back({"maximal frame", finish_copy(b)});
  }
  {
    FrameBuilder b;
    for (int i = 0; i < 124; ++i) EXPECT_TRUE(b.add(Command::NOP, 0, 0, 0).ok());
    out.push_back({"124 datagrams", finish_copy(b)});
  }
  {
    FrameBuilder b;
    EXPECT_TRUE(b.add(Command::APRD, 0, make_address(position_adp(5), 0), 4).ok());
    EXPECT_TRUE(b.add(Command::APRD, 1, make_address(position_adp(6), 0), 4).ok());
    std::vector<std::uint8_t> f = finish_copy(b);
    f.insert(f.begin() + 12, {0x81, 0x00, 0x00, 0x01});
    out.push_back({"vlan tagged", f});
  }
  return out;
}

struct Outcome {
  bool ok;
  Error error;
};

// Parses exactly `n` bytes held in their own heap block and, on success, reads every field of
// every datagram while the block is alive (the views point into it).
Outcome parse_exact(const std::vector<std::uint8_t>& source, std::size_t n) {
  const std::unique_ptr<std::uint8_t[]> block(new std::uint8_t[n == 0 ? 1 : n]);
  std::copy(source.begin(), source.begin() + static_cast<std::ptrdiff_t>(n), block.get());
  const auto r = FrameView::parse(ConstByteSpan(block.get(), n));
  if (!r.ok()) return {false, r.error()};
  std::uint32_t sum = 0;
  for (const DatagramView d : r.value()) {
    sum += d.index() + d.address() + d.length() + d.irq() + d.wkc();
    for (const std::uint8_t byte : d.data()) sum += byte;
  }
  (void)sum;
  return {true, Error{}};
}

TEST(FrameTruncation, CaptureCutAtEveryByteIsAnErrorUpToTheEndOfTheDatagrams) {
  std::size_t cuts = 0;
  for (const Sample& s : samples()) {
    const auto full = FrameView::parse(ConstByteSpan(s.bytes.data(), s.bytes.size()));
    ASSERT_TRUE(full.ok()) << s.name;
    const std::size_t ecat_end = full.value().header().ecat_end();
    for (std::size_t n = 0; n < s.bytes.size(); ++n) {
      SCOPED_TRACE(testing::Message() << s.name << " cut at " << n);
      const auto r = parse_exact(s.bytes, n);
      if (n < ecat_end) {
        ASSERT_FALSE(r.ok);
        EXPECT_EQ(r.error.code, Errc::truncated) << r.error.what;
      } else {
        EXPECT_TRUE(r.ok);  // only padding was cut
      }
      ++cuts;
    }
  }
  EXPECT_GT(cuts, 3000U);
}

TEST(FrameTruncation, EtherCATLengthCutAtEveryByteIsAnError) {
  std::size_t cuts = 0;
  for (const Sample& s : samples()) {
    const auto full = FrameView::parse(ConstByteSpan(s.bytes.data(), s.bytes.size()));
    ASSERT_TRUE(full.ok()) << s.name;
    const FrameHeader h = full.value().header();
    const std::size_t payload = h.ecat_offset + kEcatHeaderSize;
    for (std::size_t cut = payload; cut < h.ecat_end(); ++cut) {
      SCOPED_TRACE(testing::Message() << s.name << " ecat length cut at " << cut);
      std::vector<std::uint8_t> f(s.bytes.begin(), s.bytes.begin() + static_cast<std::ptrdiff_t>(cut));
      const auto word = load_le16(f.data() + h.ecat_offset);
      store_le16(f.data() + h.ecat_offset, static_cast<std::uint16_t>((word & 0xF800U) | (cut - payload)));
      const auto r = parse_exact(f, f.size());
      ASSERT_FALSE(r.ok);
      EXPECT_EQ(r.error.code, Errc::truncated) << r.error.what;
      EXPECT_NE(r.error.detail0, kFrameLevel);  // a datagram-level field noticed it
      EXPECT_LE(r.error.detail1, cut);
      ++cuts;
    }
  }
  EXPECT_GT(cuts, 3000U);
}

}  // namespace
}  // namespace rescue::ecat
