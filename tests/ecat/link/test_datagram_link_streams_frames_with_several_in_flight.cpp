// DatagramLink::stream() (the static drift compensation's FRMW frames) keeps up to `in_flight`
// frames on their way instead of waiting for each: against a NIC whose frames take 30 us to come
// back and 7 us on the wire, two in flight halve the time, the limit is never exceeded, a frame that
// never comes back is counted as lost (not waited for twice, not repeated), a late one of an earlier
// stream is ignored, and the last returned frame's data is handed back.
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

// Echoes each frame after `round_trip`, frames serialised `wire` apart, writing a counter into the
// first datagram's data and 1 into its working counter; drops the frames whose number is in `drop`.
class EchoNic final : public hal::Nic {
 public:
  static constexpr hal::Nanoseconds kRoundTrip = 30 * hal::kNsPerUs;
  static constexpr hal::Nanoseconds kWire = 7 * hal::kNsPerUs;

  Status send(ConstByteSpan frame) noexcept override {
    const hal::Nanoseconds at = clock_.now() > wire_free_ ? clock_.now() : wire_free_;
    wire_free_ = at + kWire;
    const unsigned number = sent_++;
    if (number == drop_) return Status::success();
    Pending& p = queue_[(head_ + count_) % queue_.size()];
    std::memcpy(p.bytes.data(), frame.data(), frame.size());
    p.length = frame.size();
    p.ready_at = at + kRoundTrip;
    // The first datagram's data: the frame's number (as the reference's time would be); wkc 1.
    const std::size_t data_at = kEthernetHeaderSize + 2 + 10;
    const std::size_t length = load_le16(p.bytes.data() + kEthernetHeaderSize + 2 + 6) & 0x07FFU;
    if (length >= 4) store_le32(p.bytes.data() + data_at, number);
    store_le16(p.bytes.data() + data_at + length, 1);
    ++count_;
    if (count_ > max_in_flight_) max_in_flight_ = count_;
    return Status::success();
  }
  Result<std::size_t> receive(ByteSpan buffer, hal::Nanoseconds deadline) noexcept override {
    if (count_ > 0 && queue_[head_].ready_at <= deadline) {
      Pending& p = queue_[head_];
      head_ = (head_ + 1) % queue_.size();
      --count_;
      clock_.sleep_until(p.ready_at);
      std::memcpy(buffer.data(), p.bytes.data(), p.length);
      return p.length;
    }
    clock_.sleep_until(deadline);
    return make_error(Errc::timeout, "nothing");
  }
  hal::Clock& clock() noexcept override { return clock_; }
  const char* name() const noexcept override { return "echo"; }
  hal::NicStats stats() const noexcept override { return {}; }

  void drop(unsigned number) noexcept { drop_ = number; }
  unsigned max_in_flight() const noexcept { return max_in_flight_; }
  unsigned sent() const noexcept { return sent_; }

 private:
  struct Pending {
    std::array<std::uint8_t, kMaxFrameSize> bytes{};
    std::size_t length{0};
    hal::Nanoseconds ready_at{0};
  };
  hal::VirtualClock clock_{hal::kNsPerSec};
  std::array<Pending, 16> queue_{};
  std::size_t head_{0};
  unsigned count_{0};
  unsigned max_in_flight_{0};
  unsigned sent_{0};
  unsigned drop_{~0U};
  hal::Nanoseconds wire_free_{0};
};

constexpr std::uint32_t kAddress = make_address(0x1000, 0x0910);

TEST(DatagramLinkStream, TwoInFlightHalveTheTimeAndNeverExceedTheLimit) {
  EchoNic one_nic;
  DatagramLink one(one_nic);
  std::array<std::uint8_t, 8> data{};
  const hal::Nanoseconds one_start = one_nic.clock().now();
  const auto by_one = one.stream(Command::FRMW, kAddress, ByteSpan(data), 100, 1, hal::kNsPerMs);
  ASSERT_TRUE(by_one.ok());
  const hal::Nanoseconds one_took = one_nic.clock().now() - one_start;
  EXPECT_EQ(by_one.value().returned, 100U);
  EXPECT_EQ(one_nic.max_in_flight(), 1U);

  EchoNic two_nic;
  DatagramLink two(two_nic);
  const hal::Nanoseconds two_start = two_nic.clock().now();
  const auto by_two = two.stream(Command::FRMW, kAddress, ByteSpan(data), 100, 2, hal::kNsPerMs);
  ASSERT_TRUE(by_two.ok());
  const hal::Nanoseconds two_took = two_nic.clock().now() - two_start;
  EXPECT_EQ(by_two.value().returned, 100U);
  EXPECT_EQ(by_two.value().lost, 0U);
  EXPECT_EQ(two_nic.max_in_flight(), 2U);
  EXPECT_EQ(two_nic.sent(), 100U);
  EXPECT_EQ(two.stats().exchanges, 100U);
  EXPECT_LE(two_took, one_took / 2 + EchoNic::kRoundTrip) << one_took << " ns one by one, " << two_took << " ns two at a time";
  // The last frame's data: the NIC's number of it.
  EXPECT_EQ(load_le32(data.data()), 99U);
  EXPECT_EQ(by_two.value().last_wkc, 1U);
  EXPECT_EQ(by_two.value().last_back_at, two_nic.clock().now());
}

TEST(DatagramLinkStream, AFrameThatNeverComesBackIsCountedLostOnce) {
  for (unsigned in_flight : {1U, 4U, 8U}) {
    SCOPED_TRACE(in_flight);
    EchoNic nic;
    nic.drop(10);
    DatagramLink link(nic);
    std::array<std::uint8_t, 8> data{};
    const auto streamed = link.stream(Command::FRMW, kAddress, ByteSpan(data), 50, in_flight, hal::kNsPerMs);
    ASSERT_TRUE(streamed.ok());
    EXPECT_EQ(streamed.value().returned, 49U);
    EXPECT_EQ(streamed.value().lost, 1U);
    EXPECT_EQ(nic.sent(), 50U) << "a lost frame is not repeated";
    EXPECT_EQ(nic.max_in_flight(), in_flight);
    EXPECT_EQ(link.stats().timeouts, 1U);
    EXPECT_EQ(link.stats().stale_frames, 0U);
  }
}

TEST(DatagramLinkStream, AFrameOfAnEarlierExchangeIsStaleNotCounted) {
  EchoNic nic;
  DatagramLink link(nic);
  std::array<std::uint8_t, 8> data{};
  // An exchange that gives up before its frame is back (10 us < 30 us): it turns up in the stream.
  const auto early = link.transfer(Command::FRMW, kAddress, ByteSpan(data), 10 * hal::kNsPerUs, 1);
  EXPECT_FALSE(early.ok());
  const auto streamed = link.stream(Command::FRMW, kAddress, ByteSpan(data), 20, 2, hal::kNsPerMs);
  ASSERT_TRUE(streamed.ok());
  EXPECT_EQ(streamed.value().returned, 20U);
  EXPECT_EQ(streamed.value().lost, 0U);
  EXPECT_EQ(link.stats().stale_frames, 1U);
}

TEST(DatagramLinkStream, RefusesMoreThanADatagramHolds) {
  EchoNic nic;
  DatagramLink link(nic);
  std::array<std::uint8_t, kMaxDatagramDataLength + 1> data{};
  EXPECT_FALSE(link.stream(Command::FPWR, kAddress, ByteSpan(data), 1, 1, hal::kNsPerMs).ok());
}

}  // namespace
}  // namespace rescue::ecat
