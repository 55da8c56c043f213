// `rescue-motion decode FILE` lists the same datagrams as Wireshark's dissector, line by line:
// frame number, command, index, address, length and working counter. Checked on the four real
// captures in ../shared/vectors/captures and on a capture our writer makes with every command and
// address form. tshark is part of the toolchain (toolchain/setup.sh): its absence is a failure.
#include <gtest/gtest.h>

#include <unistd.h>

#include <iostream>
#include <string>
#include <vector>

#include "ecat/capture/capture_writer.hpp"
#include "ecat/codec/frame.hpp"
#include "tests/support/run_command.hpp"
#include "tests/support/shared_captures.hpp"
#include "tests/support/tshark_listing.hpp"

namespace rescue {
namespace {

const std::string kProgram = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";
const std::string& kCaptures = test::kSharedCaptureDir;

// Runs both and compares; returns the number of datagrams compared.
std::size_t compare_listings(const std::string& capture) {
  const test::CommandOutput ours = test::run_command("'" + kProgram + "' decode '" + capture + "'");
  EXPECT_EQ(ours.exit_status, 0) << capture;
  const std::vector<std::string> our_lines = test::split_lines(ours.out);

  const test::TsharkListing theirs = test::tshark_listing(capture);
  EXPECT_EQ(theirs.exit_status, 0) << "tshark failed on " << capture;
  EXPECT_TRUE(theirs.problem.empty()) << theirs.problem;

  EXPECT_EQ(our_lines.size(), theirs.lines.size()) << capture;
  const std::size_t n = std::min(our_lines.size(), theirs.lines.size());
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (our_lines[i] != theirs.lines[i] && ++mismatches <= 10) {
      ADD_FAILURE() << capture << " line " << i + 1 << "\n  ours:   " << our_lines[i] << "\n  tshark: " << theirs.lines[i];
    }
  }
  EXPECT_EQ(mismatches, 0U);
  return n;
}

class DecodeVersusTshark : public testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(test::program_available("tshark")) << "tshark is missing: run toolchain/setup.sh (Debian package tshark)";
    ASSERT_EQ(::access(kProgram.c_str(), X_OK), 0) << kProgram << " is not built";
  }
};

TEST_F(DecodeVersusTshark, EveryCommandAndAddressFormWrittenByOurWriter) {
  const std::string path = std::string(::testing::TempDir()) + "/decode-vs-tshark-" + std::to_string(::getpid()) + ".pcapng";
  {
    ecat::CaptureWriter w;
    ASSERT_TRUE(w.open(path.c_str()).ok());
    hal::Nanoseconds t = 0;
    // One frame per command with three datagrams of that command at different addresses, then
    // the returned frame with working counters, as a master and its segment would produce.
    for (std::uint8_t raw = 0; raw < ecat::kCommandCount; ++raw) {
      const auto c = static_cast<ecat::Command>(raw);
      ecat::FrameBuilder b;
      b.reset(ecat::MacAddress{0x02, 0, 0, 0, 0, 0x01});
      ASSERT_TRUE(b.add(c, raw, ecat::make_address(ecat::position_adp(raw), 0x0130), 2).ok());
      ASSERT_TRUE(b.add(c, static_cast<std::uint8_t>(raw + 100), ecat::make_address(0x1000 + raw, 0x0910), 8, {}, 0, 3).ok());
      ASSERT_TRUE(b.add(c, 255, 0xFFFFFFFFU - raw, 0, {}, 0, 0xFFFF).ok());
      const ConstByteSpan f = b.finish();
      w.record(f, t += 1000, ecat::FrameDirection::outbound);
    }
    // Many datagrams in one frame; a maximal one; a frame that is not EtherCAT (skipped by both).
    ecat::FrameBuilder many;
    for (int i = 0; i < 124; ++i) {
      ASSERT_TRUE(many.add(static_cast<ecat::Command>(i % 15), static_cast<std::uint8_t>(i), static_cast<std::uint32_t>(i) * 0x01010101U, 0).ok());
    }
    w.record(many.finish(), t += 1000, ecat::FrameDirection::outbound);
    ecat::FrameBuilder big;
    ASSERT_TRUE(big.add(ecat::Command::LRW, 1, 0x00010000, static_cast<std::uint16_t>(ecat::kMaxDatagramDataLength), {}, 0, 21).ok());
    w.record(big.finish(), t += 1000, ecat::FrameDirection::inbound);
    std::vector<std::uint8_t> arp(60, 0);
    arp[12] = 0x08;
    arp[13] = 0x06;
    w.record(ConstByteSpan(arp.data(), arp.size()), t += 1000, ecat::FrameDirection::inbound);
  }
  const std::size_t compared = compare_listings(path);
  EXPECT_EQ(compared, 15U * 3U + 124U + 1U);
  std::cout << "[ compared ] " << compared << " datagrams of our writer's capture\n";
  ::unlink(path.c_str());
}

class SharedCaptureVersusTshark : public DecodeVersusTshark, public testing::WithParamInterface<const char*> {
 protected:
  void SetUp() override {
    DecodeVersusTshark::SetUp();
    if (::access((kCaptures + GetParam()).c_str(), R_OK) != 0) {
      GTEST_SKIP() << "no shared captures: " << kCaptures << " is absent (the data is not part of the repository)";
    }
  }
};

TEST_P(SharedCaptureVersusTshark, SameDatagramsLineByLine) {
  const std::size_t compared = compare_listings(kCaptures + GetParam());
  EXPECT_GT(compared, 500U);
  std::cout << "[ compared ] " << compared << " datagrams of " << GetParam() << "\n";
  RecordProperty("datagrams_compared", static_cast<int>(compared));
}

INSTANTIATE_TEST_SUITE_P(Captures, SharedCaptureVersusTshark,
                         testing::ValuesIn(test::kSharedCaptures),
                         test::capture_param_name);

}  // namespace
}  // namespace rescue
