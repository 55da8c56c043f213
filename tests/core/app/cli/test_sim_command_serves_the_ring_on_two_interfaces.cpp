// `rescue-motion sim --iface A --ring-iface B` serves the robot's ring configuration on two veth
// pairs (the master's main and ring ports): with the ring closed a broadcast read sent on main is
// answered by all 23 slaves and comes back on the ring interface; after `cut l_leg` on its standard
// input the same read sent on both ports comes back on each, the working counters adding up to 23;
// `restore l_leg` closes the ring again. The same interface twice is refused.
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
constexpr hal::Nanoseconds kNothingComes = 100 * hal::kNsPerMs;
constexpr int kStartTimeoutMs = 10000;
constexpr int kSlaves = 23;
constexpr const char* kRingMaster = "ecm1";
constexpr const char* kRingSlave = "ecs1";

TEST(SimRingCommand, TheSameInterfaceTwiceIsRefused) {
  ChildProcess sim;
  ASSERT_TRUE(sim.start({kBinary, "sim", "--iface", "rm-no-such0", "--ring-iface", "rm-no-such0"}));
  EXPECT_EQ(sim.wait_exit(), 1);
  EXPECT_NE(sim.output().find("--ring-iface must name another interface than --iface"), std::string::npos) << sim.output();
}

class SimRingOverVeth : public rescue::testing::NetnsTest {
 protected:
  void SetUp() override {
    NetnsTest::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    // The second pair, between the same namespaces: the ring port's cable.
    std::string out;
    ASSERT_TRUE(VethPair::ip(veth_->master_ns(), std::string("link add name ") + kRingMaster + " type veth peer name " + kRingSlave +
                                                     " netns " + veth_->slave_ns(), out))
        << out;
    ASSERT_TRUE(VethPair::ip(veth_->master_ns(), std::string("link set ") + kRingMaster + " up", out)) << out;
    ASSERT_TRUE(VethPair::ip(veth_->slave_ns(), std::string("link set ") + kRingSlave + " up", out)) << out;
    ASSERT_TRUE(sim_.start({kBinary, "sim", "--iface", VethPair::kSlaveInterface, "--ring-iface", kRingSlave, "--priority", "0",
                            "--cpu", "any"},
                           veth_->slave_ns()));
    const std::string ready = "serving 23 slaves in a ring on ecs0 (main) and ecs1 (ring)";
    ASSERT_TRUE(sim_.wait_for_output(ready, kStartTimeoutMs)) << "simulator did not start: " << sim_.output();
    InNamespace inside(veth_->master_ns());
    ASSERT_TRUE(inside.entered());
    ASSERT_TRUE(main_.open(VethPair::kMasterInterface).ok());
    ASSERT_TRUE(ring_.open(kRingMaster).ok());
  }

  void send(hal::RawSocketNic& nic, std::uint8_t index) {
    const auto frame = rescue::testing::make_brd_frame(nic.features().hardware_address, index);
    ASSERT_TRUE(nic.send(ConstByteSpan(frame.data(), frame.size())).ok());
  }
  // The working counter of the frame received on `nic` (-1: none within `wait`).
  int received_wkc(hal::RawSocketNic& nic, hal::Nanoseconds wait) {
    std::array<std::uint8_t, ecat::kMaxFrameSize> buffer{};
    const auto got = nic.receive(ByteSpan(buffer), nic.clock().now() + wait);
    if (!got.ok()) return -1;
    auto view = ecat::FrameView::parse(ConstByteSpan(buffer.data(), got.value()));
    if (!view.ok()) return -2;
    return (*view.value().begin()).wkc();
  }
  void fault(const std::string& command) {
    ASSERT_TRUE(sim_.write_input(command + "\n"));
    ASSERT_TRUE(sim_.wait_for_output("fault: ok " + command, kStartTimeoutMs)) << sim_.output();
  }

  ChildProcess sim_;
  hal::RawSocketNic main_;
  hal::RawSocketNic ring_;
};

TEST_F(SimRingOverVeth, ClosedRingReturnsMainsFrameOnTheRingPortAndACutSplitsIt) {
  send(main_, 1);
  EXPECT_EQ(received_wkc(ring_, kGenerous), kSlaves);
  EXPECT_EQ(received_wkc(main_, kNothingComes), -1);

  fault("cut l_leg");
  send(main_, 2);
  send(ring_, 3);
  const int main_wkc = received_wkc(main_, kGenerous);
  const int ring_wkc = received_wkc(ring_, kGenerous);
  EXPECT_EQ(main_wkc, 9) << "junctions and the right arm are before l_leg";
  EXPECT_EQ(main_wkc + ring_wkc, kSlaves);

  fault("restore l_leg");
  fault("cut ring");
  send(main_, 4);
  EXPECT_EQ(received_wkc(main_, kGenerous), kSlaves);
  fault("restore ring");
  send(main_, 5);
  EXPECT_EQ(received_wkc(ring_, kGenerous), kSlaves);

  EXPECT_EQ(sim_.stop(SIGTERM), 0) << sim_.output();
  EXPECT_NE(sim_.output().find("frames sent back on the other port: 2 from main, 0 from ring"), std::string::npos) << sim_.output();
}

}  // namespace
}  // namespace rescue::app
