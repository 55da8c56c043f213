// With RawSocketSettings::receive_timestamps the raw-socket NIC gives each frame the kernel's
// receive timestamp, on its monotonic clock (last_receive_time): the instant the frame reached the
// interface, not the later instant a busy reader read it. `rescue-motion sim` serves each frame at
// that time (docs/redundancy.md "DC across a break over veth"). Over a veth pair in namespaces; no
// duration is asserted, only the order of events: the frame is read long after it was sent, and
// its stamp lies between the send and the read. Without the setting there is no stamp.
#include <array>
#include <chrono>
#include <cstdint>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "hal/net/raw_socket_nic.hpp"
#include "tests/support/netns_veth.hpp"
#include "tests/support/test_frames.hpp"

namespace rescue::hal {
namespace {

using rescue::testing::InNamespace;
using rescue::testing::VethPair;

constexpr Nanoseconds kGenerous = 2 * kNsPerSec;  // only bounds a broken test
constexpr auto kReadLate = std::chrono::milliseconds(20);  // the reader busy elsewhere

Status open_in(const std::string& ns, RawSocketNic& nic, const char* iface, const RawSocketSettings& settings) {
  InNamespace inside(ns);
  if (!inside.entered()) return make_error(Errc::io_error, "setns");
  return nic.open(iface, settings);
}

class ReceiveTimestampsOverVeth : public rescue::testing::NetnsTest {
 protected:
  void SetUp() override {
    NetnsTest::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    ASSERT_TRUE(open_in(veth_->master_ns(), master_, VethPair::kMasterInterface, RawSocketSettings{}).ok());
    RawSocketSettings stamped;
    stamped.receive_timestamps = true;
    ASSERT_TRUE(open_in(veth_->slave_ns(), slaves_, VethPair::kSlaveInterface, stamped).ok());
  }

  RawSocketNic master_;
  RawSocketNic slaves_;
};

TEST_F(ReceiveTimestampsOverVeth, AFrameReadLateCarriesTheInstantItArrived) {
  ASSERT_TRUE(slaves_.features().receive_timestamps);
  std::array<std::uint8_t, 1514> buffer{};
  // The kernel turns stamping on at entry a little after the option is set (deferred work); until
  // then it stamps a frame when it is read. So: frames until one carries its arrival.
  bool stamped_at_arrival = false;
  for (std::uint8_t i = 0; i < 20 && !stamped_at_arrival; ++i) {
    const auto frame = rescue::testing::make_brd_frame(master_.features().hardware_address, i);
    const Nanoseconds before_send = slaves_.clock().now();
    ASSERT_TRUE(master_.send(ConstByteSpan(frame.data(), frame.size())).ok());
    std::this_thread::sleep_for(kReadLate);
    const Nanoseconds read_from = slaves_.clock().now();
    ASSERT_TRUE(slaves_.receive(ByteSpan(buffer), read_from + kGenerous).ok());
    const Nanoseconds read_done = slaves_.clock().now();
    const Result<Nanoseconds> arrived = slaves_.last_receive_time();
    ASSERT_TRUE(arrived.ok()) << arrived.error().what;
    EXPECT_GE(arrived.value(), before_send) << "stamped after the send began";
    EXPECT_LE(arrived.value(), read_done) << "never later than the read";
    stamped_at_arrival = arrived.value() < read_from;
  }
  EXPECT_TRUE(stamped_at_arrival) << "no frame of 20 stamped before the reader looked (at its arrival, not its read)";
}

TEST_F(ReceiveTimestampsOverVeth, WithoutTheSettingAFrameHasNoStamp) {
  const auto frame = rescue::testing::make_brd_frame(slaves_.features().hardware_address, 1);
  ASSERT_TRUE(slaves_.send(ConstByteSpan(frame.data(), frame.size())).ok());
  std::array<std::uint8_t, 1514> buffer{};
  ASSERT_TRUE(master_.receive(ByteSpan(buffer), master_.clock().now() + kGenerous).ok());
  EXPECT_FALSE(master_.features().receive_timestamps);
  const Result<Nanoseconds> arrived = master_.last_receive_time();
  ASSERT_FALSE(arrived.ok());
  EXPECT_EQ(arrived.error().code, Errc::unsupported);
}

}  // namespace
}  // namespace rescue::hal
