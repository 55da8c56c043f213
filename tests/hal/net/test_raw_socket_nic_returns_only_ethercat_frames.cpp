// The raw-socket NIC returns EtherCAT frames only: other EtherTypes, frames longer than the
// caller's buffer and our own outgoing frames never come out of receive(); the ones that reach
// user space are counted as dropped. A receive with nothing to return ends with Errc::timeout at
// (never before) its deadline.
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
constexpr Nanoseconds kQuiet = 50 * kNsPerMs;     // long enough for a frame on veth to arrive

class RawSocketNicFilters : public rescue::testing::NetnsTest {
 protected:
  void open_both(RawSocketSettings::Capture master_capture) {
    RawSocketSettings settings;
    settings.capture = master_capture;
    {
      InNamespace inside(veth_->master_ns());
      ASSERT_TRUE(inside.entered());
      ASSERT_TRUE(master_.open(VethPair::kMasterInterface, settings).ok());
    }
    InNamespace inside(veth_->slave_ns());
    ASSERT_TRUE(inside.entered());
    ASSERT_TRUE(peer_.open(VethPair::kSlaveInterface).ok());
  }
  void peer_sends(const std::vector<std::uint8_t>& frame) {
    ASSERT_TRUE(peer_.send(ConstByteSpan(frame.data(), frame.size())).ok());
  }
  Result<std::size_t> master_receives(Nanoseconds wait) {
    return master_.receive(ByteSpan(buffer_), master_.clock().now() + wait);
  }

  RawSocketNic master_;
  RawSocketNic peer_;
  std::array<std::uint8_t, ecat::kMaxFrameSize> buffer_{};
  ecat::MacAddress peer_mac_{0x02, 0, 0, 0, 0, 0x5A};
};

TEST_F(RawSocketNicFilters, KernelFilterKeepsOtherEtherTypesAway) {
  open_both(RawSocketSettings::Capture::ethercat_only);
  peer_sends(rescue::testing::make_ipv4_typed_frame(peer_mac_));
  peer_sends(rescue::testing::make_brd_frame(peer_mac_, 7));
  auto got = master_receives(kGenerous);
  ASSERT_TRUE(got.ok()) << got.error().what;
  EXPECT_EQ(load_be16(buffer_.data() + 12), 0x88A4);
  auto nothing = master_receives(kQuiet);
  ASSERT_FALSE(nothing.ok());
  EXPECT_EQ(nothing.error().code, Errc::timeout);
  EXPECT_EQ(master_.stats().frames_received, 1U);
  EXPECT_EQ(master_.stats().frames_dropped, 0U) << "the kernel filter, not user space, kept the IPv4 frame away";
}

TEST_F(RawSocketNicFilters, OtherEtherTypesReachingUserSpaceAreDroppedAndCounted) {
  open_both(RawSocketSettings::Capture::all_ethertypes);
  peer_sends(rescue::testing::make_ipv4_typed_frame(peer_mac_));
  peer_sends(rescue::testing::make_brd_frame(peer_mac_, 7));
  auto got = master_receives(kGenerous);
  ASSERT_TRUE(got.ok()) << got.error().what;
  EXPECT_EQ(load_be16(buffer_.data() + 12), 0x88A4);
  // At least the IPv4-typed frame; the kernel may add its own traffic (e.g. IPv6 neighbour discovery).
  EXPECT_GE(master_.stats().frames_dropped, 1U);
  EXPECT_EQ(master_.stats().frames_received, 1U);
}

// The kernel moves an 802.1Q tag out of the frame into metadata; the NIC puts it back, so the
// frame comes out as it was on the wire (real ESCs process tagged frames and keep the tag).
TEST_F(RawSocketNicFilters, VlanTaggedFrameComesOutWithItsTag) {
  open_both(RawSocketSettings::Capture::ethercat_only);
  std::vector<std::uint8_t> tagged = rescue::testing::make_brd_frame(peer_mac_, 11);
  const std::uint8_t tag[4] = {0x81, 0x00, 0x20, 0x07};  // priority 1, VLAN 7
  tagged.insert(tagged.begin() + 12, tag, tag + 4);
  peer_sends(tagged);
  auto got = master_receives(kGenerous);
  ASSERT_TRUE(got.ok()) << got.error().what;
  ASSERT_EQ(got.value(), tagged.size());
  EXPECT_EQ(std::vector<std::uint8_t>(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(got.value())),
            tagged);
}

TEST_F(RawSocketNicFilters, FrameLongerThanTheBufferIsDroppedNotTruncated) {
  open_both(RawSocketSettings::Capture::ethercat_only);
  ecat::FrameBuilder builder;
  builder.reset(peer_mac_);
  ASSERT_TRUE(builder.add(ecat::Command::LRW, 1, 0x10000, 1000).ok());
  const ConstByteSpan big = builder.finish();
  ASSERT_TRUE(peer_.send(big).ok());
  std::array<std::uint8_t, 100> small{};
  auto got = master_.receive(ByteSpan(small), master_.clock().now() + kQuiet);
  ASSERT_FALSE(got.ok());
  EXPECT_EQ(got.error().code, Errc::timeout);
  EXPECT_EQ(master_.stats().frames_dropped, 1U);
}

TEST_F(RawSocketNicFilters, OwnOutgoingFramesAreNeverReceived) {
  open_both(RawSocketSettings::Capture::all_ethertypes);  // the capture that does see outgoing frames
  const auto frame = rescue::testing::make_brd_frame(master_.features().hardware_address, 3);
  ASSERT_TRUE(master_.send(ConstByteSpan(frame.data(), frame.size())).ok());
  auto got = master_receives(kQuiet);
  ASSERT_FALSE(got.ok()) << "our own frame came back through the socket";
  EXPECT_EQ(got.error().code, Errc::timeout);
  // The peer did see it: the frame did go out.
  auto at_peer = peer_.receive(ByteSpan(buffer_), peer_.clock().now() + kGenerous);
  EXPECT_TRUE(at_peer.ok());
}

TEST_F(RawSocketNicFilters, ReceiveTimesOutAtTheDeadlineNotBefore) {
  open_both(RawSocketSettings::Capture::ethercat_only);
  const Nanoseconds deadline = master_.clock().now() + 20 * kNsPerMs;
  auto got = master_.receive(ByteSpan(buffer_), deadline);
  ASSERT_FALSE(got.ok());
  EXPECT_EQ(got.error().code, Errc::timeout);
  EXPECT_GE(master_.clock().now(), deadline);
  EXPECT_EQ(master_.stats().receive_timeouts, 1U);
}

}  // namespace
}  // namespace rescue::hal
