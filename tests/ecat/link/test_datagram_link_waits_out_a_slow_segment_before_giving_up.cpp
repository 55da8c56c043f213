// A repeated blocking exchange (bring-up's: DatagramLink::exchange with attempts, transfer) gives up
// only after its attempts and DatagramLink::repeat_silence() of silence since its first send (issue
// 35: over veth under load, the simulator was not run for more than 3 x 2 ms and `run --check` failed
// at identify with "no EtherCAT frame before the deadline" while 8 late frames came back). Proven on
// a NIC in virtual time that answers nothing while it sleeps and everything once awake: a segment
// asleep 20 ms is waited out (and is a timeout without the silence: the failure before); a dead one is
// given up after the silence, with the sends bounded; a single attempt (the count step's probe) is
// never extended; a clock that does not move still ends.
#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "ecat/codec/frame.hpp"
#include "ecat/link/datagram_link.hpp"
#include "hal/net/nic.hpp"
#include "hal/time/clock.hpp"

namespace rescue::ecat {
namespace {

constexpr hal::Nanoseconds kTimeout = 2 * hal::kNsPerMs;  // MasterOptions::frame_timeout
constexpr hal::Nanoseconds kSilence = 250 * hal::kNsPerMs;  // MasterOptions::repeat_silence
constexpr hal::Nanoseconds kRoundTrip = 40 * hal::kNsPerUs;

// The segment's end as a process the host may not run: each frame is echoed (working counter 1)
// kRoundTrip after it was sent, but not before `awake_at`; a dead segment echoes nothing. With
// `clock_moves` false a timeout returns without moving the clock (a clock that stands still).
struct HeldFrame {  // an echo the segment holds until its time
  hal::Nanoseconds ready_at{0};
  std::size_t length{0};
  std::array<std::uint8_t, kMaxFrameSize> bytes{};
};

class SleepyNic final : public hal::Nic {
 public:
  Status send(ConstByteSpan frame) noexcept override {
    ++sent_;
    if (dead_ || count_ == queue_.size()) return Status::success();
    HeldFrame& p = queue_[(head_ + count_) % queue_.size()];
    std::memcpy(p.bytes.data(), frame.data(), frame.size());
    p.length = frame.size();
    const hal::Nanoseconds back = clock_.now() + kRoundTrip;
    p.ready_at = back > awake_at_ ? back : awake_at_;
    const std::size_t length = load_le16(p.bytes.data() + kEthernetHeaderSize + 2 + 6) & 0x07FFU;
    store_le16(p.bytes.data() + kEthernetHeaderSize + 2 + 10 + length, 1);
    ++count_;
    return Status::success();
  }
  Result<std::size_t> receive(ByteSpan buffer, hal::Nanoseconds deadline) noexcept override {
    if (count_ > 0 && queue_[head_].ready_at <= deadline) {
      HeldFrame& p = queue_[head_];
      head_ = (head_ + 1) % queue_.size();
      --count_;
      if (p.ready_at > clock_.now()) clock_.sleep_until(p.ready_at);
      std::memcpy(buffer.data(), p.bytes.data(), p.length);
      return p.length;
    }
    if (clock_moves_) clock_.sleep_until(deadline);
    return make_error(Errc::timeout, "nothing before the deadline");
  }
  void sleep_for(hal::Nanoseconds span) noexcept { awake_at_ = clock_.now() + span; }
  void die() noexcept { dead_ = true; }
  void stop_the_clock() noexcept { clock_moves_ = false; }
  unsigned sent() const noexcept { return sent_; }
  hal::NicStats stats() const noexcept override { return {}; }
  const char* name() const noexcept override { return "sleepy"; }
  hal::Clock& clock() noexcept override { return clock_; }

 private:
  hal::VirtualClock clock_{hal::kNsPerSec};
  std::array<HeldFrame, 256> queue_{};
  std::size_t head_{0};
  std::size_t count_{0};
  hal::Nanoseconds awake_at_{0};
  unsigned sent_{0};
  bool dead_{false};
  bool clock_moves_{true};
};

constexpr std::uint32_t kAddress = make_address(0x1000, 0x0130);  // a slave's AL status

// One bring-up exchange as identify sends it: a frame of one read, 3 attempts of kTimeout.
Result<FrameView> exchange_one_read(DatagramLink& link) {
  FrameBuilder& frame = link.begin();
  const Result<DatagramSlot> slot = frame.add(Command::FPRD, link.index(), kAddress, 2, ConstByteSpan{});
  if (!slot.ok()) return slot.error();
  return link.exchange(kTimeout, 3);
}

TEST(DatagramLinkRepeatSilence, ASegmentAsleepLongerThanTheAttemptsIsWaitedOut) {
  SleepyNic nic;
  DatagramLink link(nic);
  link.set_repeat_silence(kSilence);
  nic.sleep_for(20 * hal::kNsPerMs);
  const hal::Nanoseconds start = nic.clock().now();
  const Result<FrameView> back = exchange_one_read(link);
  ASSERT_TRUE(back.ok()) << back.error().what;
  EXPECT_EQ((*back.value().begin()).wkc(), 1U);
  EXPECT_GE(nic.clock().now() - start, 20 * hal::kNsPerMs);
  EXPECT_LT(nic.clock().now() - start, 20 * hal::kNsPerMs + kTimeout + kRoundTrip);
  EXPECT_GT(nic.sent(), 3U) << "sent again every timeout while the segment slept";

  // The next exchange finds the copies the segment answered at once as stale, and its own answer.
  const Result<FrameView> next = exchange_one_read(link);
  ASSERT_TRUE(next.ok()) << next.error().what;
  EXPECT_GT(link.stats().stale_frames, 0U);
}

TEST(DatagramLinkRepeatSilence, WithoutTheSilenceTheSameSleepIsATimeout) {
  SleepyNic nic;
  DatagramLink link(nic);
  EXPECT_EQ(link.repeat_silence(), 0);
  nic.sleep_for(20 * hal::kNsPerMs);
  const Result<FrameView> back = exchange_one_read(link);
  ASSERT_FALSE(back.ok());
  EXPECT_EQ(back.error().code, Errc::timeout);
  EXPECT_EQ(nic.sent(), 3U);
}

TEST(DatagramLinkRepeatSilence, ADeadSegmentIsGivenUpAfterTheSilenceWithTheSendsBounded) {
  SleepyNic nic;
  DatagramLink link(nic);
  link.set_repeat_silence(kSilence);
  nic.die();
  const hal::Nanoseconds start = nic.clock().now();
  const Result<FrameView> back = exchange_one_read(link);
  ASSERT_FALSE(back.ok());
  EXPECT_EQ(back.error().code, Errc::timeout);
  EXPECT_GE(nic.clock().now() - start, kSilence);
  EXPECT_LE(nic.clock().now() - start, kSilence + kTimeout);
  EXPECT_LE(nic.sent(), 3U + static_cast<unsigned>(kSilence / kTimeout) + 1U);

  std::array<std::uint8_t, 2> data{};
  const hal::Nanoseconds transfer_start = nic.clock().now();
  const Result<std::uint16_t> read = link.transfer(Command::FPRD, kAddress, ByteSpan(data), kTimeout, 3);
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.error().code, Errc::timeout);
  EXPECT_GE(nic.clock().now() - transfer_start, kSilence);
  EXPECT_LE(nic.clock().now() - transfer_start, kSilence + kTimeout);
}

TEST(DatagramLinkRepeatSilence, ATransferWaitsOutTheSleepToo) {
  SleepyNic nic;
  DatagramLink link(nic);
  link.set_repeat_silence(kSilence);
  nic.sleep_for(20 * hal::kNsPerMs);
  std::array<std::uint8_t, 2> data{};
  const Result<std::uint16_t> read = link.transfer(Command::FPRD, kAddress, ByteSpan(data), kTimeout, 3);
  ASSERT_TRUE(read.ok()) << read.error().what;
  EXPECT_EQ(read.value(), 1U);
}

TEST(DatagramLinkRepeatSilence, ASingleAttemptIsAProbeAndIsNotExtended) {
  SleepyNic nic;
  DatagramLink link(nic);
  link.set_repeat_silence(kSilence);
  nic.die();
  std::array<std::uint8_t, 2> data{};
  const hal::Nanoseconds start = nic.clock().now();
  const Result<std::uint16_t> probe = link.transfer(Command::BRD, make_address(0, 0x0000), ByteSpan(data), kTimeout, 1);
  ASSERT_FALSE(probe.ok());
  EXPECT_EQ(nic.sent(), 1U);
  EXPECT_EQ(nic.clock().now() - start, kTimeout);
}

TEST(DatagramLinkRepeatSilence, AClockThatStandsStillStillEnds) {
  SleepyNic nic;
  DatagramLink link(nic);
  link.set_repeat_silence(kSilence);
  nic.die();
  nic.stop_the_clock();
  const Result<FrameView> back = exchange_one_read(link);
  ASSERT_FALSE(back.ok());
  EXPECT_EQ(nic.sent(), 3U + static_cast<unsigned>(kSilence / kTimeout) + 1U);
}

}  // namespace
}  // namespace rescue::ecat
