// Wireshark must decode every frame the product writes to a capture file as valid EtherCAT (design
// brief section 4): tshark opens our pcapng without complaint, sees each frame as eth:ethertype:ecat
// with no malformed or error-level expert items, and reads our timestamps, directions, interface
// name and lengths as we wrote them. tshark missing is a failure (toolchain/setup.sh installs it).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <string>
#include <vector>

#include "ecat/capture/capture_writer.hpp"
#include "ecat/codec/frame.hpp"
#include "tests/support/run_command.hpp"
#include "tests/support/tshark_listing.hpp"

namespace rescue::ecat {
namespace {

class WriterVersusTshark : public testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(test::program_available("tshark")) << "tshark is missing: run toolchain/setup.sh (Debian package tshark)";
    path_ = std::string(::testing::TempDir()) + "/writer-tshark-" + std::to_string(::getpid()) + ".pcapng";
  }
  void TearDown() override { ::unlink(path_.c_str()); }

  // tshark's output with its complaints (stderr) kept, but without its notice about running as root.
  std::string tshark(const std::string& args) const {
    const test::CommandOutput out = test::run_command("tshark -r '" + path_ + "' " + args + " 2>&1");
    EXPECT_EQ(out.exit_status, 0) << out.out;
    std::string kept;
    for (const std::string& line : test::split_lines(out.out)) {
      if (line.rfind("Running as user", 0) != 0) kept += line + "\n";
    }
    return kept;
  }

  std::string path_;
};

// The robot's kind of traffic: cyclic LRW + DC, and the start-up kinds (broadcast, SII, states).
std::vector<std::vector<std::uint8_t>> sample_frames() {
  std::vector<std::vector<std::uint8_t>> frames;
  auto add_frame = [&frames](FrameBuilder& b) {
    const ConstByteSpan f = b.finish();
    frames.emplace_back(f.begin(), f.end());
  };
  for (std::uint8_t raw = 0; raw < kCommandCount; ++raw) {
    FrameBuilder b;
    b.reset(MacAddress{0x02, 0, 0, 0, 0, 0x01});
    EXPECT_TRUE(b.add(static_cast<Command>(raw), raw, make_address(0x1000, 0x0130), 2).ok());
    add_frame(b);
  }
  FrameBuilder cyclic;
  EXPECT_TRUE(cyclic.add(Command::FRMW, 1, make_address(0x1000, 0x0910), 8).ok());
  for (std::uint8_t branch = 0; branch < 4; ++branch) {
    EXPECT_TRUE(cyclic.add(Command::LRW, static_cast<std::uint8_t>(2 + branch), 0x10000U * branch, 105).ok());
  }
  add_frame(cyclic);
  FrameBuilder full;
  EXPECT_TRUE(full.add(Command::LRD, 9, 0, static_cast<std::uint16_t>(kMaxDatagramDataLength)).ok());
  add_frame(full);
  return frames;
}

TEST_F(WriterVersusTshark, EveryFrameIsValidEtherCAT) {
  const auto frames = sample_frames();
  const hal::Nanoseconds base = 1'700'000'000'123'456'789LL;
  {
    CaptureWriter w;
    ASSERT_TRUE(w.open(path_.c_str(), CaptureWriterOptions{"rescue-sim", 0}).ok());
    for (std::size_t i = 0; i < frames.size(); ++i) {
      w.record(ConstByteSpan(frames[i].data(), frames[i].size()), base + static_cast<hal::Nanoseconds>(i) * 1'000'001,
               i % 2 == 0 ? FrameDirection::outbound : FrameDirection::inbound);
    }
    ASSERT_EQ(w.stats().frames_written, frames.size());
  }

  // Opened without complaint, one row per frame with what we wrote.
  const std::string rows = tshark(
      "-T fields -E separator=/t -e frame.number -e frame.protocols -e frame.packet_flags_direction "
      "-e frame.time_epoch -e frame.len -e frame.cap_len -e frame.interface_name");
  const std::vector<std::string> lines = test::split_lines(rows);
  ASSERT_EQ(lines.size(), frames.size()) << rows;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    SCOPED_TRACE(lines[i]);
    char expected_time[64];
    const hal::Nanoseconds t = base + static_cast<hal::Nanoseconds>(i) * 1'000'001;
    std::snprintf(expected_time, sizeof expected_time, "%lld.%09lld", static_cast<long long>(t / hal::kNsPerSec),
                  static_cast<long long>(t % hal::kNsPerSec));
    const std::vector<std::string> f = test::split(lines[i], '\t');
    ASSERT_EQ(f.size(), 7U);
    EXPECT_EQ(f[0], std::to_string(i + 1));
    // Ethernet, EtherCAT frame header, EtherCAT datagrams (a mailbox layer may follow).
    EXPECT_EQ(f[1].rfind("eth:ethertype:ecatf:ecat", 0), 0U) << "protocols";
    EXPECT_EQ(f[2], i % 2 == 0 ? "0x00000002" : "0x00000001") << "direction: 2 outbound, 1 inbound";
    EXPECT_EQ(f[3], expected_time) << "timestamp";
    EXPECT_EQ(f[4], std::to_string(frames[i].size())) << "frame.len";
    EXPECT_EQ(f[5], std::to_string(frames[i].size())) << "frame.cap_len";
    EXPECT_EQ(f[6], "rescue-sim") << "interface name";
  }

  // Nothing malformed, no expert item of error severity.
  const std::string bad = tshark("-Y '_ws.malformed || _ws.expert.severity >= error'");
  EXPECT_TRUE(bad.empty()) << bad;

  // The cyclic frame: five datagrams, FRMW then four LRW.
  const std::string cmds = tshark("-Y 'frame.number == 16' -T fields -E occurrence=a -E aggregator=, -e ecat.cmd");
  EXPECT_EQ(cmds, "0x0e,0x0c,0x0c,0x0c,0x0c\n");
}

}  // namespace
}  // namespace rescue::ecat
