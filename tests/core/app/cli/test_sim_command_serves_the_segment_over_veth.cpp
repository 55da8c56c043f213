// `rescue-motion sim --iface IFACE`, the built binary, serves the simulated segment on one end of a
// veth pair; the raw-socket NIC on the other end exchanges real frames with it as a master would
// with the robot: every slave answers, the frame comes back marked by the ESCs, SIGTERM stops the
// simulator cleanly with its counters. Also: a missing interface is a one-line error.
#include <signal.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ecat/codec/frame.hpp"
#include "hal/net/raw_socket_nic.hpp"
#include "tests/support/child_process.hpp"
#include "tests/support/netns_veth.hpp"
#include "tests/support/test_frames.hpp"

namespace rescue::app {
namespace {

using rescue::testing::ChildProcess;
using rescue::testing::InNamespace;
using rescue::testing::VethPair;

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";
constexpr hal::Nanoseconds kGenerous = 2 * hal::kNsPerSec;  // only bounds a broken test
constexpr int kStartTimeoutMs = 10000;
constexpr std::size_t kSlaves = 23;  // 2 junction slaves + 21 joints (design brief section 2)

TEST(SimCommand, MissingInterfaceIsAOneLineErrorWithExitStatus1) {
  ChildProcess sim;
  ASSERT_TRUE(sim.start({kBinary, "sim", "--iface", "rm-no-such0"}));
  EXPECT_EQ(sim.wait_exit(), 1);
  EXPECT_NE(sim.output().find("rescue-motion sim: cannot open rm-no-such0: no such network interface"),
            std::string::npos)
      << sim.output();
}

class SimCommandOverVeth : public rescue::testing::NetnsTest {
 protected:
  void SetUp() override {
    NetnsTest::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    ASSERT_TRUE(sim_.start({kBinary, "sim", "--iface", VethPair::kSlaveInterface}, veth_->slave_ns()));
    const std::string ready = "serving " + std::to_string(kSlaves) + " slaves on " + VethPair::kSlaveInterface;
    if (!sim_.wait_for_output(ready, kStartTimeoutMs)) {
      if (sim_.output().find("not in this build yet") != std::string::npos) {
        GTEST_SKIP() << "the simulated segment is not on this branch yet: " << sim_.output();
      }
      FAIL() << "simulator did not start: " << sim_.output();
    }
    InNamespace inside(veth_->master_ns());
    ASSERT_TRUE(inside.entered());
    ASSERT_TRUE(master_.open(VethPair::kMasterInterface).ok());
  }

  // Sends `frame` and returns the frame that comes back (empty on timeout).
  std::vector<std::uint8_t> round_trip(const std::vector<std::uint8_t>& frame) {
    EXPECT_TRUE(master_.send(ConstByteSpan(frame.data(), frame.size())).ok());
    std::array<std::uint8_t, ecat::kMaxFrameSize> buffer{};
    auto got = master_.receive(ByteSpan(buffer), master_.clock().now() + kGenerous);
    if (!got.ok()) return {};
    return std::vector<std::uint8_t>(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(got.value()));
  }

  ChildProcess sim_;
  hal::RawSocketNic master_;
};

TEST_F(SimCommandOverVeth, EverySlaveAnswersABroadcastReadAndTheFrameComesBackMarked) {
  const ecat::MacAddress source = master_.features().hardware_address;
  const auto reply = round_trip(rescue::testing::make_brd_frame(source, 17));
  ASSERT_FALSE(reply.empty()) << "no frame came back from the simulator";
  auto view = ecat::FrameView::parse(ConstByteSpan(reply.data(), reply.size()));
  ASSERT_TRUE(view.ok()) << view.error().what;
  const auto datagram = *view.value().begin();
  EXPECT_EQ(datagram.index(), 17);
  EXPECT_EQ(datagram.wkc(), kSlaves);
  EXPECT_EQ(datagram.adp(), kSlaves) << "each slave increments ADP of a broadcast datagram";
  ecat::MacAddress marked = source;
  marked[0] |= 0x02;
  EXPECT_EQ(view.value().header().source, marked);
  EXPECT_EQ(view.value().header().destination, ecat::kBroadcastMac);

  EXPECT_EQ(sim_.stop(SIGTERM), 0) << sim_.output();
  EXPECT_NE(sim_.output().find("frames received: 1\n"), std::string::npos) << sim_.output();
  EXPECT_NE(sim_.output().find("frames returned: 1\n"), std::string::npos) << sim_.output();
}

TEST_F(SimCommandOverVeth, AThousandFramesAllComeBack) {
  const ecat::MacAddress source = master_.features().hardware_address;
  for (int i = 0; i < 1000; ++i) {
    const auto index = static_cast<std::uint8_t>(i);
    const auto reply = round_trip(rescue::testing::make_brd_frame(source, index));
    ASSERT_FALSE(reply.empty()) << "frame " << i << " did not come back";
    auto view = ecat::FrameView::parse(ConstByteSpan(reply.data(), reply.size()));
    ASSERT_TRUE(view.ok());
    ASSERT_EQ((*view.value().begin()).index(), index);
  }
  EXPECT_EQ(sim_.stop(SIGINT), 0) << sim_.output();
  EXPECT_NE(sim_.output().find("frames returned: 1000\n"), std::string::npos) << sim_.output();
}

}  // namespace
}  // namespace rescue::app
