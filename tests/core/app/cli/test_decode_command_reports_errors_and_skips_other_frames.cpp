// `rescue-motion decode` follows the design brief's rules beyond the happy path: frames that are
// not EtherCAT (other EtherTypes) are skipped, frames of a link type it cannot read are left out
// and named on stderr with a non-zero status, malformed EtherCAT frames print `frame ERROR reason`
// and the listing goes on, zero padding after the last datagram prints `frame PAD n`, Linux cooked
// captures (SLL, SLL2) list like Ethernet ones, a classic pcap file works like a pcapng one, and a
// file that cannot be read (missing, a FIFO with no writer) ends at once with a non-zero status and
// one line saying why.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <string>
#include <vector>

#include "core/base/endian.hpp"
#include "ecat/codec/frame.hpp"
#include "tests/support/capture_bytes.hpp"
#include "tests/support/run_command.hpp"

namespace rescue {
namespace {

const std::string kProgram = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

class DecodeCommand : public testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(::access(kProgram.c_str(), X_OK), 0) << kProgram << " is not built";
    dir_ = std::string(::testing::TempDir());
  }
  void TearDown() override {
    for (const std::string& p : written_) ::unlink(p.c_str());
  }
  std::string write(const char* name, const std::vector<std::uint8_t>& bytes) {
    const std::string path = dir_ + "/" + name + "-" + std::to_string(::getpid());
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    written_.push_back(path);
    return path;
  }
  // stdout and stderr apart: stderr goes to a file. `timeout` turns a hang into status 124.
  test::CommandOutput decode(const std::string& path, std::string* err) {
    const std::string err_path = dir_ + "/decode-stderr-" + std::to_string(::getpid());
    const test::CommandOutput out =
        test::run_command("timeout 10 '" + kProgram + "' decode '" + path + "' 2>'" + err_path + "'");
    std::ifstream in(err_path);
    err->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    ::unlink(err_path.c_str());
    return out;
  }

  std::string dir_;
  std::vector<std::string> written_;
};

std::vector<std::uint8_t> ecat_frame() {
  ecat::FrameBuilder b;
  EXPECT_TRUE(b.add(ecat::Command::FPRD, 7, ecat::make_address(0x1001, 0x0130), 2, {}, 0, 1).ok());
  EXPECT_TRUE(b.add(ecat::Command::LRW, 8, 0x00010000, 4, {}, 0, 3).ok());
  const ConstByteSpan f = b.finish();
  return std::vector<std::uint8_t>(f.begin(), f.end());
}

std::vector<std::uint8_t> arp_frame() {
  std::vector<std::uint8_t> f(60, 0);
  f[12] = 0x08;
  f[13] = 0x06;
  return f;
}

std::vector<std::uint8_t> bad_length_frame() {
  auto f = ecat_frame();
  f[16 + 6] = 0xFF;  // first datagram claims 0x7FF bytes
  f[16 + 7] = 0x07;
  return f;
}

TEST_F(DecodeCommand, SkipsOtherFramesAndReportsMalformedOnes) {
  test::PcapngBuilder ng(false);
  ng.interface()                      // interface 0: Ethernet
      .interface(101)                 // interface 1: raw IP, never EtherCAT
      .packet(0, 1, ecat_frame())     // frame 1
      .packet(0, 2, arp_frame())      // frame 2: skipped
      .packet(0, 3, bad_length_frame())
      .packet(1, 4, ecat_frame())     // frame 4: other link type, left out and named
      .packet(0, 5, std::vector<std::uint8_t>(10, 0xFF))  // frame 5: shorter than an Ethernet header
      .packet(0, 6, ecat_frame());
  std::string err;
  const test::CommandOutput out = decode(write("mixed.pcapng", ng.bytes()), &err);
  EXPECT_EQ(out.exit_status, 1) << err;
  EXPECT_EQ(err,
            "rescue-motion decode: 1 frame(s) not decoded: link type 101 is not supported (1 Ethernet, 113 Linux "
            "cooked SLL, 276 Linux cooked SLL2)\n");
  EXPECT_EQ(out.out,
            "1 FPRD 7 0x1001:0x0130 2 1\n"
            "1 LRW 8 0x00010000 4 3\n"
            "3 ERROR datagram length: truncated (datagram 0, offset 22)\n"
            "5 ERROR ethernet header: truncated (offset 0)\n"
            "6 FPRD 7 0x1001:0x0130 2 1\n"
            "6 LRW 8 0x00010000 4 3\n");
}

// A 1-byte BWR in a frame whose EtherCAT header says 14: one zero byte of padding.
std::vector<std::uint8_t> padded_bwr_frame(std::uint8_t pad_byte) {
  ecat::FrameBuilder b;
  EXPECT_TRUE(b.add(ecat::Command::BWR, 5, ecat::make_address(0, 0x0120), 1, {}, 0, 3).ok());
  const ConstByteSpan f = b.finish();
  std::vector<std::uint8_t> bytes(f.begin(), f.end());
  store_le16(bytes.data() + 14, static_cast<std::uint16_t>(0x1000 | 14));
  bytes[16 + 13] = pad_byte;
  return bytes;
}

TEST_F(DecodeCommand, PaddingAfterTheLastDatagramPrintsAsPadding) {
  test::PcapngBuilder ng(false);
  ng.interface().packet(0, 1, padded_bwr_frame(0x00)).packet(0, 2, padded_bwr_frame(0xA5));
  std::string err;
  const test::CommandOutput out = decode(write("padded.pcapng", ng.bytes()), &err);
  EXPECT_EQ(out.exit_status, 0) << err;
  EXPECT_EQ(out.out,
            "1 BWR 5 0x0000:0x0120 1 3\n"
            "1 PAD 1\n"
            "2 ERROR bytes after last datagram: malformed (datagram 1, offset 29)\n");
}

std::vector<std::uint8_t> cooked(bool v2, const std::vector<std::uint8_t>& ethernet, std::uint16_t protocol) {
  std::vector<std::uint8_t> p;
  if (v2) {
    p = {static_cast<std::uint8_t>(protocol >> 8), static_cast<std::uint8_t>(protocol), 0, 0, 0, 0, 0, 2, 0, 1, 4, 6, 2, 0, 0, 0, 0, 1, 0, 0};
  } else {
    p = {0, 4, 0, 1, 0, 6, 2, 0, 0, 0, 0, 1, 0, 0, static_cast<std::uint8_t>(protocol >> 8), static_cast<std::uint8_t>(protocol)};
  }
  p.insert(p.end(), ethernet.begin() + 14, ethernet.end());
  return p;
}

TEST_F(DecodeCommand, LinuxCookedCapturesListLikeEthernet) {
  for (const bool v2 : {false, true}) {
    const std::uint16_t link = v2 ? 276 : 113;
    test::PcapngBuilder ng(false);
    ng.interface(link)
        .packet(0, 1, cooked(v2, ecat_frame(), 0x88A4))
        .packet(0, 2, cooked(v2, arp_frame(), 0x0806))  // skipped: not EtherCAT
        .packet(0, 3, cooked(v2, padded_bwr_frame(0), 0x88A4))
        .packet(0, 4, std::vector<std::uint8_t>(v2 ? 19 : 15, 0));  // shorter than the cooked header
    std::string err;
    const test::CommandOutput out = decode(write(v2 ? "sll2.pcapng" : "sll.pcapng", ng.bytes()), &err);
    EXPECT_EQ(out.exit_status, 0) << err;
    EXPECT_EQ(out.out,
              "1 FPRD 7 0x1001:0x0130 2 1\n"
              "1 LRW 8 0x00010000 4 3\n"
              "3 BWR 5 0x0000:0x0120 1 3\n"
              "3 PAD 1\n"
              "4 ERROR sll header: truncated (offset 0)\n")
        << "link type " << link;
    test::PcapBuilder pcap(false, false, link);  // classic pcap with the same link type
    pcap.record(1, 2, cooked(v2, ecat_frame(), 0x88A4));
    const test::CommandOutput out2 = decode(write(v2 ? "sll2.pcap" : "sll.pcap", pcap.bytes()), &err);
    EXPECT_EQ(out2.exit_status, 0) << err;
    EXPECT_EQ(out2.out, "1 FPRD 7 0x1001:0x0130 2 1\n1 LRW 8 0x00010000 4 3\n");
  }
}

TEST_F(DecodeCommand, UnsupportedLinkTypeAloneFailsNonZero) {
  test::PcapBuilder pcap(false, false, 101);
  pcap.record(1, 2, ecat_frame());
  std::string err;
  const test::CommandOutput out = decode(write("rawip.pcap", pcap.bytes()), &err);
  EXPECT_EQ(out.exit_status, 1);
  EXPECT_EQ(out.out, "");
  EXPECT_NE(err.find("link type 101 is not supported"), std::string::npos) << err;
}

// Before the fix `decode` hung in open() forever (status 124 from `timeout` here).
TEST_F(DecodeCommand, FifoWithoutAWriterIsRefusedAtOnce) {
  const std::string fifo = dir_ + "/decode-fifo-" + std::to_string(::getpid());
  ::unlink(fifo.c_str());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  written_.push_back(fifo);
  std::string err;
  const test::CommandOutput out = decode(fifo, &err);
  EXPECT_EQ(out.exit_status, 1) << err;
  EXPECT_NE(err.find("not a regular file"), std::string::npos) << err;
}

TEST_F(DecodeCommand, ReadsClassicPcapInBothByteOrders) {
  for (const bool big : {false, true}) {
    test::PcapBuilder pcap(big, !big);
    pcap.record(1, 2, ecat_frame()).record(3, 4, arp_frame()).record(5, 6, ecat_frame());
    std::string err;
    const test::CommandOutput out = decode(write(big ? "be.pcap" : "le.pcap", pcap.bytes()), &err);
    EXPECT_EQ(out.exit_status, 0) << err;
    EXPECT_EQ(out.out,
              "1 FPRD 7 0x1001:0x0130 2 1\n"
              "1 LRW 8 0x00010000 4 3\n"
              "3 FPRD 7 0x1001:0x0130 2 1\n"
              "3 LRW 8 0x00010000 4 3\n");
  }
}

TEST_F(DecodeCommand, MissingFileFailsWithOneLine) {
  std::string err;
  const test::CommandOutput out = decode(dir_ + "/does-not-exist.pcapng", &err);
  EXPECT_NE(out.exit_status, 0);
  EXPECT_EQ(out.out, "");
  EXPECT_EQ(test::split_lines(err).size(), 1U) << err;
  EXPECT_NE(err.find("No such file or directory"), std::string::npos) << err;
}

TEST_F(DecodeCommand, NotACaptureFailsWithOneLine) {
  std::string err;
  const test::CommandOutput out = decode(write("text.txt", {'h', 'e', 'l', 'l', 'o', '\n'}), &err);
  EXPECT_NE(out.exit_status, 0);
  EXPECT_EQ(test::split_lines(err).size(), 1U) << err;
  EXPECT_NE(err.find("file format"), std::string::npos) << err;
}

TEST_F(DecodeCommand, TruncatedCapturePrintsWhatItReadThenFails) {
  test::PcapngBuilder ng(false);
  ng.interface().packet(0, 1, ecat_frame()).packet(0, 2, ecat_frame());
  auto bytes = ng.bytes();
  bytes.resize(bytes.size() - 10);
  std::string err;
  const test::CommandOutput out = decode(write("cut.pcapng", bytes), &err);
  EXPECT_NE(out.exit_status, 0);
  EXPECT_EQ(out.out, "1 FPRD 7 0x1001:0x0130 2 1\n1 LRW 8 0x00010000 4 3\n");
  ASSERT_EQ(test::split_lines(err).size(), 1U) << err;
  EXPECT_NE(err.find("block length: truncated (frame 2"), std::string::npos) << err;
}

TEST_F(DecodeCommand, WithoutAFileItSaysHowToCallIt) {
  const test::CommandOutput out = test::run_command("'" + kProgram + "' decode 2>&1");
  EXPECT_EQ(out.exit_status, 2);
  EXPECT_NE(out.out.find("usage: rescue-motion decode FILE"), std::string::npos) << out.out;
}

}  // namespace
}  // namespace rescue
