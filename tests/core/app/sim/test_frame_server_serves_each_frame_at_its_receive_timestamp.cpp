// The serve loop behind `rescue-motion sim` gives the segment each frame at the NIC's receive
// timestamp (hal::Nic::last_receive_time), the instant the frame reached the interface, however
// late it was read; never later than the read; and at the read when the NIC has no stamp. Over
// veth this is what lets the two copies of a ring frame pass the slaves when they were sent, not
// one after the other as the simulator gets to them (docs/redundancy.md). Virtual time, fake NIC.
#include <cstdint>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "core/app/sim/frame_server.hpp"
#include "tests/support/test_frames.hpp"

namespace rescue::app {
namespace {

constexpr ecat::MacAddress kMasterMac{0x00, 0x1B, 0x21, 0x0A, 0x0B, 0x0C};

// One frame waiting, with the stamp the kernel gave it (or none); read after `read_at` on its clock.
class StampingNic final : public hal::Nic {
 public:
  Status send(ConstByteSpan /*frame*/) noexcept override { return Status::success(); }
  Result<std::size_t> receive(ByteSpan buffer, hal::Nanoseconds /*deadline*/) noexcept override {
    const auto frame = rescue::testing::make_brd_frame(kMasterMac, 1);
    std::memcpy(buffer.data(), frame.data(), frame.size());
    clock_.sleep_until(read_at);
    return frame.size();
  }
  Result<hal::Nanoseconds> last_receive_time() const noexcept override {
    if (!stamps) return make_error(Errc::unsupported, "no stamps");
    return stamp;
  }
  hal::Clock& clock() noexcept override { return clock_; }
  const char* name() const noexcept override { return "stamping"; }
  hal::NicStats stats() const noexcept override { return {}; }

  bool stamps{true};
  hal::Nanoseconds stamp{0};
  hal::Nanoseconds read_at{0};

 private:
  hal::VirtualClock clock_{0};
};

class ArrivalRecorder final : public FrameProcessor {
 public:
  std::size_t slave_count() const noexcept override { return 1; }
  Result<std::size_t> process(ByteSpan frame, hal::Nanoseconds arrival) noexcept override {
    arrivals.push_back(arrival);
    return frame.size();
  }
  std::vector<hal::Nanoseconds> arrivals;
};

TEST(FrameServerArrival, AFrameReadLateIsServedAtItsReceiveTimestamp) {
  StampingNic nic;
  ArrivalRecorder segment;
  FrameServer server(nic, segment);
  nic.stamp = 1'000'000;
  nic.read_at = 1'400'000;  // the host gave the simulator the CPU 400 us after the frame came
  ASSERT_TRUE(server.serve_one(2'000'000).ok());
  ASSERT_EQ(segment.arrivals.size(), 1U);
  EXPECT_EQ(segment.arrivals[0], 1'000'000);
  EXPECT_EQ(server.last_arrival(), 1'000'000);
  EXPECT_EQ(server.last_read_delay(), 400'000);
  EXPECT_EQ(server.counters().frames_timestamped, 1U);
}

TEST(FrameServerArrival, TwoCopiesReadOneAfterTheOtherPassAtTheirOwnStamps) {
  // The main copy and the ring copy of one frame, sent 3 us apart, read 300 us apart.
  StampingNic main_port;
  StampingNic ring_port;
  ArrivalRecorder segment;
  FrameServer main_server(main_port, segment);
  FrameServer ring_server(ring_port, segment);
  main_port.stamp = 5'000'000;
  main_port.read_at = 5'050'000;
  ring_port.stamp = 5'003'000;
  ring_port.read_at = 5'350'000;
  ASSERT_TRUE(main_server.serve_one(6'000'000).ok());
  ASSERT_TRUE(ring_server.serve_one(6'000'000).ok());
  ASSERT_EQ(segment.arrivals.size(), 2U);
  EXPECT_EQ(segment.arrivals[1] - segment.arrivals[0], 3'000) << "the sends' spacing, not the reads'";
}

TEST(FrameServerArrival, AStampLaterThanTheReadIsTakenAsTheRead) {
  StampingNic nic;
  ArrivalRecorder segment;
  FrameServer server(nic, segment);
  nic.stamp = 2'000'000;
  nic.read_at = 1'500'000;
  ASSERT_TRUE(server.serve_one(3'000'000).ok());
  EXPECT_EQ(segment.arrivals.at(0), 1'500'000);
}

TEST(FrameServerArrival, WithoutAStampTheFrameIsServedAtTheRead) {
  StampingNic nic;
  ArrivalRecorder segment;
  FrameServer server(nic, segment);
  nic.stamps = false;
  nic.read_at = 700'000;
  ASSERT_TRUE(server.serve_one(1'000'000).ok());
  EXPECT_EQ(segment.arrivals.at(0), 700'000);
  EXPECT_EQ(server.counters().frames_timestamped, 0U);
}

}  // namespace
}  // namespace rescue::app
