// The capture tap sees the master's traffic as it happens: a DatagramLink exchanging frames with
// the simulated robot through the loopback NIC, with a CaptureWriter on its tap, leaves a pcapng
// file holding each sent frame (outbound) followed by its returned frame (inbound, working counter
// filled in by the 23 slaves), stamped with the virtual clock's time of each event.
#include <gtest/gtest.h>

#include <unistd.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "drivers/sim/segment/simulated_nic.hpp"
#include "ecat/capture/capture_tap.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/link/datagram_link.hpp"
#include "tests/support/read_frames.hpp"
#include "tests/support/segment_test_support.hpp"

namespace rescue::ecat {
namespace {

TEST(CaptureTap, RecordsEverySentAndReturnedFrameInOrder) {
  const std::string path = std::string(::testing::TempDir()) + "/tap-" + std::to_string(::getpid()) + ".pcapng";
  auto rig = drivers::testing::Rig::robot();
  hal::VirtualClock clock(5 * hal::kNsPerSec);
  drivers::SimulatedNic nic(rig->segment, clock);
  DatagramLink link(nic);
  CaptureWriter capture;
  ASSERT_TRUE(capture.open(path.c_str()).ok());
  link.set_tap(capture_tap, &capture);

  std::array<std::uint8_t, 2> type{};
  const auto counted = link.transfer(Command::BRD, make_address(0, reg::kType), ByteSpan(type), hal::kNsPerMs);
  ASSERT_TRUE(counted.ok());
  EXPECT_EQ(counted.value(), kSlaveCount);
  std::array<std::uint8_t, 2> status{};
  const auto read = link.transfer(Command::APRD, make_address(position_adp(22), reg::kAlStatus), ByteSpan(status), hal::kNsPerMs);
  ASSERT_TRUE(read.ok());
  EXPECT_EQ(read.value(), 1);
  ASSERT_TRUE(capture.close().ok());
  EXPECT_EQ(capture.stats().frames_written, 4U);
  EXPECT_EQ(capture.stats().write_errors, 0U);

  std::ifstream in(path, std::ios::binary);
  const std::vector<std::uint8_t> file{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const auto frames = test::read_all_frames(file);
  ASSERT_EQ(frames.size(), 4U);
  const FrameDirection expected[] = {FrameDirection::outbound, FrameDirection::inbound, FrameDirection::outbound,
                                     FrameDirection::inbound};
  const std::uint16_t wkc[] = {0, kSlaveCount, 0, 1};
  for (std::size_t i = 0; i < frames.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(frames[i].direction, expected[i]);
    const auto view = FrameView::parse(frames[i].bytes);
    ASSERT_TRUE(view.ok());
    EXPECT_EQ((*view.value().begin()).wkc(), wkc[i]);
    if (i > 0) {
      EXPECT_GE(frames[i].timestamp_ns, frames[i - 1].timestamp_ns);
    }
  }
  // The round trip through 23 slaves takes tens of microseconds of virtual time.
  EXPECT_GT(frames[1].timestamp_ns - frames[0].timestamp_ns, 10'000U);
  EXPECT_EQ(frames[0].timestamp_ns, static_cast<std::uint64_t>(5 * hal::kNsPerSec));
  ::unlink(path.c_str());
}

}  // namespace
}  // namespace rescue::ecat
