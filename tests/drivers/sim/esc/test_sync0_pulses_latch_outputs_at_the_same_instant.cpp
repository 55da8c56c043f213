// SYNC0: once the clocks are synchronised and every joint's SYNC0 unit is started at the same
// system time with the same cycle, the joints latch their outputs at the same true instant (within
// a few nanoseconds), every cycle, on their own clocks. Also the SYNC0 registers' behaviour: the
// start time reads back as the next pulse, a start time in the past waits for the 32-bit wrap.
#include <cstdio>

#include "tests/support/dc_master_steps.hpp"

namespace rescue::drivers::testing {
namespace {

constexpr hal::Nanoseconds kCycle = hal::kNsPerMs;
constexpr std::uint64_t kMasterTime = 1'000'000'000'000ULL;
constexpr std::uint32_t kLogical = 0x00010000;

std::uint32_t logical_of(std::size_t p) { return kLogical + static_cast<std::uint32_t>(p) * (kOutputBytes + kInputBytes); }

// One cycle: process data for every joint (one LRW) and the reference time (FRMW).
void cycle(Rig& rig) {
  const std::size_t bytes = (kOutputBytes + kInputBytes) * kSlaveCount;
  (void)rig.exchange(Command::LRW, kLogical, std::vector<std::uint8_t>(bytes, 0x5A), 10 * hal::kNsPerUs);
  distribute_reference_time(rig, kCycle - 10 * hal::kNsPerUs);
}

class Sync0 : public ::testing::Test {
 protected:
  void SetUp() override {
    rig = Rig::robot();
    prepare_distributed_clocks(*rig, kMasterTime, true);
    for (int i = 0; i < 3000; ++i) distribute_reference_time(*rig, kCycle);
    // Every joint to SAFE-OP with its mailbox and process data configured.
    for (std::size_t p = 0; p < kSlaveCount; ++p) {
      if (kSlaves[p].kind != SlaveKind::joint_drive) continue;
      const std::uint16_t station = kSlaves[p].station_address;
      configure_mailbox(*rig, station);
      ASSERT_EQ(request_state(*rig, station, AlState::pre_op), 0x0002);
      configure_process_data(*rig, station, logical_of(p));
      ASSERT_EQ(request_state(*rig, station, AlState::safe_op), 0x0004);
    }
  }

  // Starts SYNC0 on every joint at `start` (system time), `kCycle` apart.
  void start_sync0(std::uint64_t start) {
    for (std::size_t p = 0; p < kSlaveCount; ++p) {
      if (kSlaves[p].kind != SlaveKind::joint_drive) continue;
      const std::uint16_t station = kSlaves[p].station_address;
      EXPECT_EQ(rig->write(Command::FPWR, station, reg::kDcSync0CycleTime, le32(static_cast<std::uint32_t>(kCycle))).wkc, 1);
      EXPECT_EQ(rig->write(Command::FPWR, station, reg::kDcStartTime, le64(start)).wkc, 1);
      EXPECT_EQ(rig->write(Command::FPWR, station, reg::kDcActivation, {0x03}).wkc, 1);
    }
  }

  std::uint64_t reference_time() { return from_le(rig->read(Command::FPRD, kStationAddressBase, reg::kDcSystemTime, 8).data); }

  std::unique_ptr<Rig> rig;
};

TEST_F(Sync0, AllJointsLatchOutputsAtTheSameInstant) {
  const std::uint64_t start = (reference_time() / kCycle + 50) * kCycle;  // 50 cycles ahead, on a cycle boundary
  start_sync0(start);
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    if (kSlaves[p].kind != SlaveKind::joint_drive) continue;
    EXPECT_EQ(rig->read16(kSlaves[p].station_address, reg::kDcActivationStatus) & 0x01, 0x01);  // first pulse pending
    EXPECT_EQ(from_le(rig->read(Command::FPRD, kSlaves[p].station_address, reg::kDcStartTime, 8).data), start);
  }
  for (int i = 0; i < 20; ++i) cycle(*rig);  // process data flowing: SAFE-OP -> OP can complete
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    if (kSlaves[p].kind == SlaveKind::joint_drive) {
      ASSERT_EQ(request_state(*rig, kSlaves[p].station_address, AlState::op), 0x0008) << kSlaves[p].name;
    }
  }
  for (int i = 0; i < 200; ++i) cycle(*rig);

  hal::Nanoseconds earliest = 0;
  hal::Nanoseconds latest = 0;
  std::uint64_t pulse = 0;
  bool first = true;
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    if (kSlaves[p].kind != SlaveKind::joint_drive) continue;
    const Esc& esc = rig->segment.esc(p);
    const OutputLatch latch = esc.last_output_latch();
    EXPECT_EQ(latch.trigger, CycleTrigger::sync0) << kSlaves[p].name;
    EXPECT_EQ((latch.system_time - start) % kCycle, 0u) << kSlaves[p].name;  // on the SYNC0 grid
    if (first) {
      pulse = latch.system_time;
      earliest = latest = latch.segment_time;
      first = false;
    }
    EXPECT_EQ(latch.system_time, pulse) << kSlaves[p].name;  // everybody's last pulse is the same pulse
    earliest = std::min(earliest, latch.segment_time);
    latest = std::max(latest, latch.segment_time);
    // The device ran its cycle at SYNC0, not on the frame's arrival.
    EXPECT_EQ(rig->device_at(p).cycles.back().trigger, CycleTrigger::sync0);
  }
  std::printf("sync0: 21 joints latched pulse %llu within %lld ns of each other\n", static_cast<unsigned long long>(pulse),
              static_cast<long long>(latest - earliest));
  EXPECT_LE(latest - earliest, 5);
}

TEST_F(Sync0, StartTimeInThePastWaitsForTheLow32BitsToComeRound) {
  const std::uint64_t now = reference_time();
  const std::uint64_t past = now - 10 * hal::kNsPerMs;
  const std::uint16_t station = kSlaves[2].station_address;
  EXPECT_EQ(rig->write(Command::FPWR, station, reg::kDcSync0CycleTime, le32(static_cast<std::uint32_t>(kCycle))).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, station, reg::kDcStartTime, le64(past)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, station, reg::kDcActivation, {0x03}).wkc, 1);
  const std::uint64_t first_pulse = from_le(rig->read(Command::FPRD, station, reg::kDcStartTime, 8).data);
  EXPECT_EQ(static_cast<std::uint32_t>(first_pulse), static_cast<std::uint32_t>(past));
  EXPECT_GT(first_pulse, now);
  EXPECT_LE(first_pulse - now, std::uint64_t{1} << 32);
}

TEST_F(Sync0, DeactivationStopsThePulses) {
  const std::uint64_t start = (reference_time() / kCycle + 5) * kCycle;
  start_sync0(start);
  for (int i = 0; i < 20; ++i) cycle(*rig);
  EXPECT_EQ(rig->write(Command::BWR, 0, reg::kDcActivation, {0x00}).wkc, kSlaveCount);
  const std::uint64_t pulses = rig->segment.esc(2).counters().sync0_pulses;
  EXPECT_GT(pulses, 10u);
  for (int i = 0; i < 20; ++i) cycle(*rig);
  EXPECT_EQ(rig->segment.esc(2).counters().sync0_pulses, pulses);
}

TEST_F(Sync0, Sync0StatusIsSetByAPulseAndClearedByReadingIt) {
  const std::uint64_t start = (reference_time() / kCycle + 2) * kCycle;
  start_sync0(start);
  for (int i = 0; i < 5; ++i) cycle(*rig);
  EXPECT_EQ(rig->read(Command::FPRD, kSlaves[2].station_address, reg::kDcSync0Status, 1).data[0] & 0x01, 0x01);
  EXPECT_EQ(rig->read(Command::FPRD, kSlaves[2].station_address, reg::kDcSync0Status, 1).data[0] & 0x01, 0x00);
}

}  // namespace
}  // namespace rescue::drivers::testing
