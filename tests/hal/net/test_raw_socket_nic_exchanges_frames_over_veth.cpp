// The raw-socket NIC sends and receives real EtherCAT frames through the kernel: a master end and
// an echo responder (playing the slave chain) on the two ends of a veth pair in namespaces.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ecat/codec/frame.hpp"
#include "hal/net/raw_socket_nic.hpp"
#include "tests/support/netns_veth.hpp"
#include "tests/support/test_frames.hpp"

namespace rescue::hal {
namespace {

using rescue::testing::InNamespace;
using rescue::testing::VethPair;

constexpr Nanoseconds kGenerous = 2 * kNsPerSec;  // only bounds a broken test; never a timing check

Status open_in(const std::string& ns, RawSocketNic& nic, const char* iface,
               const RawSocketSettings& settings = RawSocketSettings{}) {
  InNamespace inside(ns);
  if (!inside.entered()) return make_error(Errc::io_error, "setns");
  return nic.open(iface, settings);
}

// What the slave chain does to the frame, reduced to what the test can check: every datagram's
// working counter incremented and the source MAC marked as an ESC marks it.
void echo_one(RawSocketNic& slaves) {
  std::array<std::uint8_t, ecat::kMaxFrameSize> buffer{};
  auto got = slaves.receive(ByteSpan(buffer), slaves.clock().now() + kGenerous);
  ASSERT_TRUE(got.ok()) << got.error().what;
  auto view = ecat::MutableFrameView::parse(ByteSpan(buffer.data(), got.value()));
  ASSERT_TRUE(view.ok()) << view.error().what;
  for (auto datagram : view.value()) datagram.set_wkc(static_cast<std::uint16_t>(datagram.wkc() + 1));
  buffer[6] |= 0x02;
  ASSERT_TRUE(slaves.send(ConstByteSpan(buffer.data(), got.value())).ok());
}

class RawSocketNicOverVeth : public rescue::testing::NetnsTest {
 protected:
  void SetUp() override {
    NetnsTest::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    ASSERT_TRUE(open_in(veth_->master_ns(), master_, VethPair::kMasterInterface).ok());
    ASSERT_TRUE(open_in(veth_->slave_ns(), slaves_, VethPair::kSlaveInterface).ok());
    source_ = master_.features().hardware_address;
  }

  RawSocketNic master_;
  RawSocketNic slaves_;
  ecat::MacAddress source_{};
};

TEST_F(RawSocketNicOverVeth, FrameTravelsToTheSlavesAndComesBackProcessed) {
  const auto sent = rescue::testing::make_brd_frame(source_, 42);
  ASSERT_TRUE(master_.send(ConstByteSpan(sent.data(), sent.size())).ok());
  echo_one(slaves_);

  std::array<std::uint8_t, ecat::kMaxFrameSize> buffer{};
  auto got = master_.receive(ByteSpan(buffer), master_.clock().now() + kGenerous);
  ASSERT_TRUE(got.ok()) << got.error().what;
  ASSERT_EQ(got.value(), sent.size());
  auto view = ecat::FrameView::parse(ConstByteSpan(buffer.data(), got.value()));
  ASSERT_TRUE(view.ok());
  ASSERT_EQ(view.value().datagram_count(), 1U);
  const auto datagram = *view.value().begin();
  EXPECT_EQ(datagram.index(), 42);
  EXPECT_EQ(datagram.wkc(), 1);
  EXPECT_EQ(view.value().header().source[0], source_[0] | 0x02);
  EXPECT_EQ(view.value().header().destination, ecat::kBroadcastMac);

  EXPECT_EQ(master_.stats().frames_sent, 1U);
  EXPECT_EQ(master_.stats().frames_received, 1U);
  EXPECT_EQ(slaves_.stats().frames_received, 1U);
  EXPECT_EQ(slaves_.stats().frames_sent, 1U);
}

TEST_F(RawSocketNicOverVeth, HundredFramesReturnInOrder) {
  for (int i = 0; i < 100; ++i) {
    const auto index = static_cast<std::uint8_t>(i);
    const auto sent = rescue::testing::make_brd_frame(source_, index);
    ASSERT_TRUE(master_.send(ConstByteSpan(sent.data(), sent.size())).ok());
    echo_one(slaves_);
    std::array<std::uint8_t, ecat::kMaxFrameSize> buffer{};
    auto got = master_.receive(ByteSpan(buffer), master_.clock().now() + kGenerous);
    ASSERT_TRUE(got.ok()) << "frame " << i << ": " << got.error().what;
    auto view = ecat::FrameView::parse(ConstByteSpan(buffer.data(), got.value()));
    ASSERT_TRUE(view.ok());
    EXPECT_EQ((*view.value().begin()).index(), index);
  }
  EXPECT_EQ(master_.stats().frames_received, 100U);
  EXPECT_EQ(master_.stats().frames_dropped, 0U);
}

// A master that wakes up after its deadline (a slow host) still gets the frame that came back in
// time: a timeout means the queue was empty at the deadline, never "the process was late to look".
TEST_F(RawSocketNicOverVeth, AFrameQueuedBeforeALateLookIsReturnedNotTimedOut) {
  const auto sent = rescue::testing::make_brd_frame(source_, 7);
  ASSERT_TRUE(master_.send(ConstByteSpan(sent.data(), sent.size())).ok());
  echo_one(slaves_);
  const Nanoseconds deadline = master_.clock().now();  // already over when receive() first looks
  master_.clock().sleep_until(deadline + 5 * kNsPerMs);  // the reply is queued by now
  std::array<std::uint8_t, ecat::kMaxFrameSize> buffer{};
  auto got = master_.receive(ByteSpan(buffer), deadline);
  ASSERT_TRUE(got.ok()) << got.error().what;
  EXPECT_EQ(got.value(), sent.size());
  EXPECT_EQ(master_.stats().receive_timeouts, 0U);
  // And with nothing queued, the past deadline is a timeout at once, counted.
  got = master_.receive(ByteSpan(buffer), deadline);
  ASSERT_FALSE(got.ok());
  EXPECT_EQ(got.error().code, Errc::timeout);
  EXPECT_EQ(master_.stats().receive_timeouts, 1U);
}

TEST_F(RawSocketNicOverVeth, OpenSetsPromiscuousQdiscBypassAndReceiveBuffer) {
  const RawSocketFeatures& f = master_.features();
  EXPECT_TRUE(f.promiscuous);
  EXPECT_TRUE(f.qdisc_bypass);
  EXPECT_GT(f.interface_index, 0);
  EXPECT_GE(f.receive_buffer_bytes, RawSocketSettings{}.receive_buffer_bytes);
  EXPECT_NE(f.hardware_address, ecat::MacAddress{});
  EXPECT_STREQ(master_.name(), "raw:ecm0");

  // A packet-socket membership raises the device's promiscuity count (`ip -d link`), not the
  // IFF_PROMISC flag an administrator sets; closing the socket drops it again.
  std::string link;
  ASSERT_TRUE(VethPair::ip(veth_->master_ns(), "-d link show ecm0", link));
  EXPECT_NE(link.find("promiscuity 1"), std::string::npos) << link;
  master_.close();
  ASSERT_TRUE(VethPair::ip(veth_->master_ns(), "-d link show ecm0", link));
  EXPECT_NE(link.find("promiscuity 0"), std::string::npos) << "closing must leave the interface as it was: " << link;
}

}  // namespace
}  // namespace rescue::hal
