// Issue 35, item 6: `rescue-motion decode` read the whole file into memory first (a 2 GiB sparse file
// took 12 s and 2.1 GB before failing at byte 0). It now streams the capture through a 1 MiB window:
// under a 400 MB address-space limit (ulimit -v) a 2 GiB sparse file fails at byte 0 as "file format"
// (before: "allocate: Cannot allocate memory"), and a capture of many windows lists every frame.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <unistd.h>

#include <fstream>
#include <string>
#include <vector>

#include "core/base/sanitizers.hpp"
#include "ecat/codec/frame.hpp"
#include "tests/support/capture_bytes.hpp"
#include "tests/support/run_command.hpp"
#include "tests/support/temp_directory.hpp"

namespace rescue {
namespace {

const std::string kProgram = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

using DecodeStreaming = testing::TempDirectoryTest;

// `decode PATH` with the address space capped: a whole 2 GiB file cannot be held.
test::CommandOutput decode_capped(const std::string& path) {
  return test::run_command("ulimit -v 400000 && timeout 60 '" + kProgram + "' decode '" + path + "' 2>&1");
}

TEST_F(DecodeStreaming, ATwoGibSparseFileFailsAtByteZeroWithoutBeingReadIntoMemory) {
  // The memory cap (ulimit -v) leaves AddressSanitizer no room for its shadow memory.
  if (kAddressSanitizer) GTEST_SKIP() << "ulimit -v and AddressSanitizer's shadow memory exclude each other";
  const std::string sparse = path("sparse.pcapng");
  const int fd = ::open(sparse.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::ftruncate(fd, off_t{2} << 30), 0);
  (void)::close(fd);
  const test::CommandOutput out = decode_capped(sparse);
  EXPECT_EQ(out.exit_status, 1) << out.out;
  EXPECT_NE(out.out.find("file format: unsupported (frame 1, byte 0)"), std::string::npos) << out.out;
}

TEST_F(DecodeStreaming, ACaptureOfManyWindowsListsEveryFrame) {
  // The memory cap (ulimit -v) leaves AddressSanitizer no room for its shadow memory.
  if (kAddressSanitizer) GTEST_SKIP() << "ulimit -v and AddressSanitizer's shadow memory exclude each other";
  ecat::FrameBuilder b;
  ASSERT_TRUE(b.add(ecat::Command::FPRD, 7, ecat::make_address(0x1001, 0x0130), 2, {}, 0, 1).ok());
  const ConstByteSpan f = b.finish();
  std::vector<std::uint8_t> frame(f.begin(), f.end());
  frame.resize(1400, 0);  // Ethernet padding after the EtherCAT frame: ignored by the decoder
  test::PcapngBuilder ng;
  ng.interface();
  constexpr std::uint32_t kFrames = 8000;  // about 11 MB: eleven windows
  for (std::uint32_t i = 0; i < kFrames; ++i) ng.packet(0, i, frame);
  const std::string capture = path("many.pcapng");
  std::ofstream(capture, std::ios::binary)
      .write(reinterpret_cast<const char*>(ng.bytes().data()), static_cast<std::streamsize>(ng.bytes().size()));
  const test::CommandOutput out = decode_capped(capture);
  ASSERT_EQ(out.exit_status, 0) << out.out.substr(0, 2000);
  std::size_t lines = 0;
  for (const char c : out.out) lines += c == '\n' ? 1 : 0;
  EXPECT_EQ(lines, kFrames);
  EXPECT_NE(out.out.find("8000 FPRD 7 0x1001:0x0130 2 1\n"), std::string::npos);
}

}  // namespace
}  // namespace rescue
