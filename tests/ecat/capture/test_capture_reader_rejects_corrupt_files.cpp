// Capture files are untrusted input. Each kind of damage gives its documented error value (field,
// frame number, byte offset; see ecat/capture/capture_reader.hpp), errors are sticky, and a file cut at
// any byte or with any byte overwritten is read without a single access outside the file: every
// variant is held in a heap block of exactly its size, so the asan preset catches stray reads.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "ecat/capture/capture_reader.hpp"
#include "ecat/codec/frame.hpp"
#include "tests/support/capture_bytes.hpp"

namespace rescue::ecat {
namespace {

std::vector<std::uint8_t> frame_bytes() {
  FrameBuilder b;
  EXPECT_TRUE(b.add(Command::LRW, 1, 0x10000, 6).ok());
  const ConstByteSpan f = b.finish();
  return std::vector<std::uint8_t>(f.begin(), f.end());
}

struct Outcome {
  bool opened{false};
  std::size_t frames{0};
  Error error{};  // code ok when the whole file was read
};

// Opens and reads the whole file from an exactly-sized heap copy, touching every frame byte.
Outcome read_exact(const std::vector<std::uint8_t>& file) {
  Outcome o;
  const std::unique_ptr<std::uint8_t[]> block(new std::uint8_t[file.empty() ? 1 : file.size()]);
  if (!file.empty()) std::memcpy(block.get(), file.data(), file.size());
  auto reader = CaptureReader::open(ConstByteSpan(block.get(), file.size()));
  if (!reader.ok()) {
    o.error = reader.error();
    return o;
  }
  o.opened = true;
  CapturedFrame f;
  for (;;) {
    const Result<bool> more = reader.value().next(f);
    if (!more.ok()) {
      o.error = more.error();
      const Result<bool> again = reader.value().next(f);  // errors are sticky
      EXPECT_FALSE(again.ok());
      if (!again.ok()) {
        EXPECT_STREQ(again.error().what, o.error.what);
      }
      return o;
    }
    if (!more.value()) return o;
    unsigned sum = 0;
    for (const std::uint8_t byte : f.bytes) sum += byte;
    (void)sum;
    ++o.frames;
  }
}

void expect_error(const std::vector<std::uint8_t>& file, Errc code, const char* what, std::uint32_t frame,
                  std::uint32_t offset) {
  const Outcome o = read_exact(file);
  EXPECT_EQ(o.error.code, code) << to_string(o.error.code) << " " << o.error.what;
  EXPECT_STREQ(o.error.what, what);
  EXPECT_EQ(o.error.detail0, frame) << what;
  EXPECT_EQ(o.error.detail1, offset) << what;
}

std::vector<std::uint8_t> good_pcapng() {
  test::PcapngBuilder ng(false);
  ng.interface(capture::kLinkTypeEthernet, 0, std::uint8_t{9}).packet(0, 1, frame_bytes(), 1U).packet(0, 2, frame_bytes());
  return ng.bytes();
}
// SHB 28 bytes, IDB 32 bytes (with if_tsresol), so the first packet block starts at 60.
constexpr std::uint32_t kFirstPacket = 60;

std::vector<std::uint8_t> good_pcap() {
  test::PcapBuilder p(false, true);
  p.record(1, 2, frame_bytes()).record(3, 4, frame_bytes());
  return p.bytes();
}

void put32(std::vector<std::uint8_t>& f, std::size_t at, std::uint32_t v) { store_le32(f.data() + at, v); }

TEST(CaptureReaderErrors, ReferenceFilesAreRead) {
  EXPECT_EQ(read_exact(good_pcapng()).frames, 2U);
  EXPECT_EQ(read_exact(good_pcapng()).error.code, Errc::ok);
  EXPECT_EQ(read_exact(good_pcap()).frames, 2U);
  EXPECT_EQ(read_exact(good_pcapng()).opened, true);
}

TEST(CaptureReaderErrors, FileHeader) {
  expect_error({}, Errc::truncated, "file header", 1, 0);
  expect_error({0xD4, 0xC3, 0xB2}, Errc::truncated, "file header", 1, 0);
  auto pcap = good_pcap();
  pcap.resize(23);
  expect_error(pcap, Errc::truncated, "file header", 1, 0);
  auto ng = good_pcapng();
  ng.resize(27);
  expect_error(ng, Errc::truncated, "file header", 1, 0);
  expect_error({'h', 'e', 'l', 'l', 'o', ' ', 'w', 'o', 'r', 'l', 'd'}, Errc::unsupported, "file format", 1, 0);
}

TEST(CaptureReaderErrors, PcapVersionAndRecords) {
  auto f = good_pcap();
  f[4] = 3;
  expect_error(f, Errc::version, "pcap version", 1, 4);

  f = good_pcap();
  f.resize(f.size() + 10);  // a third record header cut short
  expect_error(f, Errc::truncated, "pcap record header", 3, static_cast<std::uint32_t>(good_pcap().size()));

  f = good_pcap();
  const std::uint32_t second = 24 + 16 + static_cast<std::uint32_t>(frame_bytes().size());
  put32(f, second + 8, 300000);
  expect_error(f, Errc::malformed, "pcap record length", 2, second + 8);

  f = good_pcap();
  put32(f, second + 8, static_cast<std::uint32_t>(frame_bytes().size() + 1));
  expect_error(f, Errc::truncated, "pcap record data", 2, second + 8);
}

TEST(CaptureReaderErrors, BlockFraming) {
  auto f = good_pcapng();
  const auto end = static_cast<std::uint32_t>(f.size());
  f.resize(f.size() + 8, 0);
  expect_error(f, Errc::truncated, "block header", 3, end);

  f = good_pcapng();
  put32(f, kFirstPacket + 4, 10);
  expect_error(f, Errc::malformed, "block length", 1, kFirstPacket + 4);
  put32(f, kFirstPacket + 4, 13);
  expect_error(f, Errc::malformed, "block length", 1, kFirstPacket + 4);
  put32(f, kFirstPacket + 4, 0xFFFFFFF0U);
  expect_error(f, Errc::truncated, "block length", 1, kFirstPacket + 4);

  f = good_pcapng();
  const std::uint32_t first_length = load_le32(f.data() + kFirstPacket + 4);
  put32(f, kFirstPacket + first_length - 4, first_length + 4);
  expect_error(f, Errc::malformed, "block trailer", 1, kFirstPacket + first_length - 4);
}

TEST(CaptureReaderErrors, SectionHeader) {
  auto f = good_pcapng();
  f[12] = 2;  // major version
  expect_error(f, Errc::version, "pcapng version", 1, 12);

  f = good_pcapng();
  put32(f, 8, 0x11223344);
  expect_error(f, Errc::malformed, "byte-order magic", 1, 8);

  // A second section whose magic is wrong.
  test::PcapngBuilder ng(false);
  ng.interface().packet(0, 1, frame_bytes()).section(false);
  f = ng.bytes();
  const std::size_t second = f.size() - 28;
  put32(f, second + 8, 0);
  expect_error(f, Errc::malformed, "byte-order magic", 2, static_cast<std::uint32_t>(second + 8));

  // A section header too short for its fixed fields (24 bytes), then an IDB.
  test::ByteBuffer b;
  b.u32(capture::kBlockSectionHeader);
  b.u32(24);
  b.u32(capture::kByteOrderMagic);
  b.u16(1);
  b.u16(0);
  b.u32(0);
  b.u32(24);
  b.raw(std::vector<std::uint8_t>(12, 0));
  expect_error(b.bytes, Errc::malformed, "block body", 1, 4);
}

TEST(CaptureReaderErrors, PacketBlocks) {
  // Interface description with no body.
  test::PcapngBuilder ng(false);
  ng.block(capture::kBlockInterfaceDescription, {});
  expect_error(ng.bytes(), Errc::malformed, "block body", 1, 28 + 4);

  // Enhanced packet block shorter than its fixed fields.
  test::PcapngBuilder short_epb(false);
  short_epb.interface().block(capture::kBlockEnhancedPacket, std::vector<std::uint8_t>(16, 0));
  expect_error(short_epb.bytes(), Errc::malformed, "block body", 1, 28 + 20 + 4);

  // Simple packet block without its length; simple packet without an interface.
  test::PcapngBuilder short_spb(false);
  short_spb.interface().block(capture::kBlockSimplePacket, {});
  expect_error(short_spb.bytes(), Errc::malformed, "block body", 1, 28 + 20 + 4);
  test::PcapngBuilder orphan(false);
  orphan.simple_packet(frame_bytes());
  expect_error(orphan.bytes(), Errc::out_of_range, "interface id", 1, 28);

  // Captured length beyond the block body.
  auto f = good_pcapng();
  put32(f, kFirstPacket + 20, 1000);
  expect_error(f, Errc::malformed, "captured length", 1, kFirstPacket + 20);

  // Packet on an interface the section did not describe.
  f = good_pcapng();
  put32(f, kFirstPacket + 8, 1);
  expect_error(f, Errc::out_of_range, "interface id", 1, kFirstPacket + 8);

  // Timestamp that overflows 64-bit nanoseconds at microsecond resolution.
  test::PcapngBuilder late(false);
  late.interface().packet(0, 0xFFFFFFFFFFFFFFFFULL, frame_bytes());
  expect_error(late.bytes(), Errc::out_of_range, "timestamp", 1, 28 + 20 + 12);
}

TEST(CaptureReaderErrors, InterfaceOptionsAndCount) {
  test::PcapngBuilder fine_resolution(false);
  fine_resolution.interface(capture::kLinkTypeEthernet, 0, std::uint8_t{30});
  expect_error(fine_resolution.bytes(), Errc::unsupported, "if_tsresol", 1, 28 + 16 + 4);

  test::PcapngBuilder long_option(false);
  long_option.interface(capture::kLinkTypeEthernet, 0, std::uint8_t{9});
  auto f = long_option.bytes();
  f[28 + 16 + 2] = 9;  // if_tsresol claims 9 bytes; 4 are left before the trailer
  expect_error(f, Errc::malformed, "option length", 1, 28 + 16 + 2);

  test::PcapngBuilder many(false);
  for (int i = 0; i < 17; ++i) many.interface();
  expect_error(many.bytes(), Errc::capacity_exceeded, "interfaces", 1, 28 + 16 * 20);

  // Option inside a packet block running past the body.
  test::PcapngBuilder flags(false);
  flags.interface().packet(0, 1, frame_bytes(), 1U);
  f = flags.bytes();
  const std::size_t option = 28 + 20 + 28 + frame_bytes().size();
  f[option + 2] = 200;
  expect_error(f, Errc::malformed, "option length", 1, static_cast<std::uint32_t>(option + 2));
}

TEST(CaptureReaderErrors, CutAtEveryByteIsAnErrorOrACleanEndAtABoundary) {
  // Boundaries inside the file: pcapng after the SHB, after the IDB, after packet 1; pcap after
  // the file header and after record 1.
  const std::vector<std::pair<std::vector<std::uint8_t>, std::size_t>> cases{{good_pcapng(), 3}, {good_pcap(), 2}};
  for (const auto& [file, boundaries] : cases) {
    const Outcome full = read_exact(file);
    ASSERT_EQ(full.frames, 2U);
    std::size_t clean_ends = 0;
    for (std::size_t n = 0; n < file.size(); ++n) {
      SCOPED_TRACE(testing::Message() << "cut at " << n);
      const std::vector<std::uint8_t> cut(file.begin(), file.begin() + static_cast<std::ptrdiff_t>(n));
      const Outcome o = read_exact(cut);
      if (o.error.code == Errc::ok) {
        ++clean_ends;  // cut exactly between two records
        EXPECT_LT(o.frames, 2U);
      } else {
        EXPECT_EQ(o.error.code, Errc::truncated) << o.error.what;
      }
    }
    EXPECT_EQ(clean_ends, boundaries);
  }
}

TEST(CaptureReaderErrors, OverwritingAnyByteNeverReadsOutOfBounds) {
  for (const auto& file : {good_pcapng(), good_pcap()}) {
    for (std::size_t i = 0; i < file.size(); ++i) {
      for (const std::uint8_t v : {std::uint8_t{0x00}, std::uint8_t{0xFF}, std::uint8_t{0x7F}}) {
        auto f = file;
        f[i] = v;
        const Outcome o = read_exact(f);
        EXPECT_LE(o.frames, f.size() / capture::kPcapRecordHeaderSize);  // every record takes >= 16 bytes
      }
    }
  }
}

}  // namespace
}  // namespace rescue::ecat
