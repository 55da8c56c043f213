// Test support: the simulated robot's ring configuration on virtual time (RobotSegmentOptions::ring,
// both master ports as a SimulatedNicPair) and the master's JointBus on it with the ring plan; the
// places a single cut opens. Heap allocated by the test (the objects are large); nothing here is
// firmware.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>

#include "drivers/joint/joint_bus.hpp"
#include "drivers/joint/robot_ring_network_plan.hpp"
#include "drivers/sim/segment/simulated_nic.hpp"
#include "drivers/sim/segment/simulated_robot.hpp"
#include "hal/time/clock.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::testing {

// Cable k < kSlaveCount: the cable into position k's port 0; kRingCable: the ring-return cable.
constexpr std::size_t kRingCable = kSlaveCount;

inline drivers::RobotSegmentOptions ring_robot_options() {
  drivers::RobotSegmentOptions options;
  options.ring = true;
  return options;
}

// Stands in front of the pair's main port: passes every frame through, except the next one after
// hold_next(), which it keeps until release() (so that the ring copy of the same exchange is walked
// first, as the simulator over veth may serve the two ports in either order). It also plays a host
// that holds the returning frames (a preempted master process): after hold_receives_until(t) no
// frame is received on the main port before t, nor on a ring NIC that asks sit_out_hold() first.
class MainPortFront final : public hal::Nic {
 public:
  explicit MainPortFront(drivers::SimulatedNic& main) noexcept : main_(main) {}

  void hold_next() noexcept { hold_ = true; }
  void hold_receives_until(hal::Nanoseconds until) noexcept { receives_held_until_ = until; }
  // Waits out the host's hold when it ends by `deadline` (true: receive now), else waits until the
  // deadline (false: nothing is received by then).
  bool sit_out_hold(hal::Nanoseconds deadline) noexcept {
    hal::Clock& clock = main_.clock();
    if (clock.now() >= receives_held_until_) return true;
    const bool ends = receives_held_until_ <= deadline;
    clock.sleep_until(ends ? receives_held_until_ : deadline);
    return ends;
  }
  // Sends the frame held, if any.
  void release() noexcept {
    if (held_ == 0) return;
    EXPECT_TRUE(main_.send(ConstByteSpan(frame_.data(), held_)).ok());
    held_ = 0;
  }

  Status send(ConstByteSpan frame) noexcept override {
    if (!hold_ || frame.size() > frame_.size()) return main_.send(frame);
    hold_ = false;
    std::memcpy(frame_.data(), frame.data(), frame.size());
    held_ = frame.size();
    return Status::success();
  }
  Result<std::size_t> receive(ByteSpan buffer, hal::Nanoseconds deadline) noexcept override {
    if (!sit_out_hold(deadline)) return make_error(Errc::timeout, "held by the host");
    return main_.receive(buffer, deadline);
  }
  hal::Clock& clock() noexcept override { return main_.clock(); }
  const char* name() const noexcept override { return main_.name(); }
  hal::NicStats stats() const noexcept override { return main_.stats(); }

 private:
  drivers::SimulatedNic& main_;
  std::array<std::uint8_t, drivers::SimulatedNic::kMaxFrame> frame_{};
  std::size_t held_{0};
  bool hold_{false};
  hal::Nanoseconds receives_held_until_{0};
};

struct RingRobotRig {
  hal::VirtualClock clock{hal::kNsPerSec};
  drivers::SimulatedRobot robot{ring_robot_options(), clock.now()};
  drivers::SimulatedNicPair nics{robot.segment(), clock};
  MainPortFront main_front{nics.main()};
  drivers::JointBus bus{main_front, drivers::kRobotRingNetworkPlan};
  drivers::JointReferences references{};

  drivers::JointCycleResult cycle(drivers::JointFeedback& feedback) {
    clock.sleep_until(bus.next_wakeup());
    return bus.cycle(references, feedback);
  }

  // Cuts (`cut` true) or restores `cable`.
  Status change(std::size_t cable, bool cut) {
    drivers::SimulatedSegment& segment = robot.segment();
    if (cable == kRingCable) return cut ? segment.cut_ring_cable() : segment.restore_ring_cable();
    return cut ? segment.cut_link(cable) : segment.restore_link(cable);
  }
  Status cut(std::size_t cable) { return change(cable, true); }
  Status restore(std::size_t cable) { return change(cable, false); }
};

// The master brought up with `ring` as its ring NIC (the pair's ring port, or a NIC standing in
// front of it) and `options`, and cycled to OP.
inline void bring_ring_to_op(RingRobotRig& rig, hal::Nic& ring, const ecat::MasterOptions& options = fast_options()) {
  rig.bus.master().use_ring(ring);
  EXPECT_TRUE(rig.robot.status().ok()) << rig.robot.status().error().what;
  EXPECT_TRUE(rig.nics.status().ok()) << rig.nics.status().error().what;
  const Status up = rig.bus.bring_up(options);
  EXPECT_TRUE(up.ok()) << describe_master_failure(rig.bus.master());
  if (!up.ok()) return;
  drivers::JointFeedback fb{};
  for (int i = 0; i < 200 && rig.bus.master().state() != ecat::MasterState::op; ++i) (void)rig.cycle(fb);
  EXPECT_EQ(rig.bus.master().state(), ecat::MasterState::op) << describe_master_failure(rig.bus.master());
}

// The place a cut of `cable` opens: the last slave the main port reaches and the first the ring port does.
inline std::uint8_t place_before(std::size_t cable) {
  return cable == 0 ? ecat::kMainPort : static_cast<std::uint8_t>(cable - 1);
}
inline std::uint8_t place_after(std::size_t cable) {
  return cable == kRingCable ? ecat::kRingPort : static_cast<std::uint8_t>(cable);
}

// Cycles `cycles` periods, then drops the ring's and the links' reports so far.
inline void cycle_and_drop_reports(RingRobotRig& rig, int cycles) {
  drivers::JointFeedback fb{};
  for (int i = 0; i < cycles; ++i) (void)rig.cycle(fb);
  ecat::RingReport ring_report;
  while (rig.bus.master().pop_ring_report(ring_report)) {
  }
  drivers::JointLinkReport link_report;
  while (rig.bus.pop_report(link_report)) {
  }
}

// The ring's report of `kind`, once, at the place of `cable`, and no other.
inline void expect_one_ring_report(ecat::Master& master, ecat::RingEventKind kind, std::size_t cable) {
  ecat::RingReport report;
  ASSERT_TRUE(master.pop_ring_report(report)) << "cable " << cable << ": no " << to_string(kind) << " report";
  EXPECT_EQ(report.kind, kind) << "cable " << cable;
  EXPECT_EQ(report.before, place_before(cable)) << "cable " << cable;
  EXPECT_EQ(report.after, place_after(cable)) << "cable " << cable;
  while (master.pop_ring_report(report)) {
    ADD_FAILURE() << "cable " << cable << ": a second report " << to_string(report.kind) << " between "
                  << static_cast<unsigned>(report.before) << " and " << static_cast<unsigned>(report.after);
  }
}

}  // namespace rescue::testing
