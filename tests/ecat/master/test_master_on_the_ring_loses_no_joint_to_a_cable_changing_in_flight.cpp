// The redundant master on the simulated robot's ring, with each cut and each repair falling while a
// frame is in flight: between the walk of the main copy and that of the ring copy, as the simulator
// over veth (`sim --iface A --ring-iface B`) applies a fault command between the two copies it serves.
// A repair in flight is the hard case: the main copy turns at the break (the slaves before it
// processed, back on the main NIC), the ring copy then goes round the closed ring unprocessed (back
// on the main NIC too): the slaves after the break are in neither copy. The master must not lose
// those joints for that cycle, nor report the cycle as a second break (docs/redundancy.md, "A cable
// changing while a frame is in flight"). Over veth the simulator may also serve the ring port first:
// then the ring copy is walked before the change and the main copy after it. A repair that way: the
// ring copy turned at the break (the slaves after it processed), the main copy went round the closed
// ring and processed every slave: the slaves after the break processed twice, their working counters
// too high, every joint's cycle short unless the exchange is repeated. Over veth the host may also
// hold the first copies (a preempted master process) until shortly before the receive deadline: the
// repeat must still be answered.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>

#include "tests/support/ring_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using testing::kRingCable;
constexpr int kCyclesPerStep = 20;

// Which copy of the exchange is walked before the fault falls.
enum class FirstCopy { main, ring };
// Whether the host holds the copies of the exchange in which the fault falls until kHostHoldEnd
// before the cycle's receive deadline (Master::cycle_deadlines), as a loaded host did over veth: too
// late for the repeat to come back by the deadline (here a repeat's round trip is 106-128 us: 100
// Mbit/s and 21 slaves), early enough for it to come back before the next period's send.
// Or the host holds the master between its two sends (the main copy out, the ring copy not yet) for
// kHoldBetweenSends, the change falling in that hold: as over veth, where the main copy's send
// returned 74-829 us late in the cycle a fault command fell in (`compare-ring-with-soem.sh`; such an
// exchange took up to 1.37 ms), so that both first copies were back only past the repeat limit.
enum class HostHold { none, until_near_the_deadline, between_the_sends };
constexpr hal::Nanoseconds kHostHoldEnd = 80 * hal::kNsPerUs;
constexpr hal::Nanoseconds kHoldBetweenSends = 1300 * hal::kNsPerUs;

// The ring NIC with a fault applied to the segment between the walks of the two copies of the next
// exchange: after the main copy went round (FirstCopy::main), or after the ring copy did, the main
// copy held back until then (FirstCopy::ring), as the simulator over veth serves either port first.
class FaultInFlight final : public hal::Nic {
 public:
  explicit FaultInFlight(testing::RingRobotRig& rig) noexcept : rig_(rig) {}

  // The fault to fall in the next exchange: cut (true) or restore (false) `cable`.
  void arm(std::size_t cable, bool cut, FirstCopy first, HostHold hold) noexcept {
    cable_ = cable;
    cut_ = cut;
    first_ = first;
    hold_ = hold;
    armed_ = true;
    if (first == FirstCopy::ring) rig_.main_front.hold_next();
  }
  bool armed() const noexcept { return armed_; }

  Status send(ConstByteSpan frame) noexcept override {
    if (!armed_) return rig_.nics.ring().send(frame);
    armed_ = false;
    if (hold_ == HostHold::until_near_the_deadline) rig_.main_front.hold_receives_until(receive_deadline() - kHostHoldEnd);
    if (hold_ == HostHold::between_the_sends) rig_.clock.sleep_until(rig_.clock.now() + kHoldBetweenSends);
    if (first_ == FirstCopy::main) {
      EXPECT_TRUE(rig_.change(cable_, cut_).ok()) << "cable " << cable_;
      return rig_.nics.ring().send(frame);
    }
    const Status sent = rig_.nics.ring().send(frame);
    EXPECT_TRUE(rig_.change(cable_, cut_).ok()) << "cable " << cable_;
    rig_.main_front.release();
    return sent;
  }
  Result<std::size_t> receive(ByteSpan buffer, hal::Nanoseconds deadline) noexcept override {
    if (!rig_.main_front.sit_out_hold(deadline)) return make_error(Errc::timeout, "held by the host");
    return rig_.nics.ring().receive(buffer, deadline);
  }
  hal::Clock& clock() noexcept override { return rig_.clock; }
  const char* name() const noexcept override { return rig_.nics.ring().name(); }
  hal::NicStats stats() const noexcept override { return rig_.nics.ring().stats(); }

 private:
  // The master's receive deadline of the exchange being sent now (MasterOptions: the cycle's deadline rule).
  hal::Nanoseconds receive_deadline() const noexcept {
    const MasterOptions& options = rig_.bus.master().options();
    const hal::Nanoseconds sent_at = rig_.clock.now();
    hal::Nanoseconds deadline = rig_.bus.next_wakeup() + options.cycle_time - options.cycle_receive_guard;
    deadline = std::min(deadline, sent_at + options.cycle_time);
    return std::max(deadline, sent_at + options.cycle_receive_timeout);
  }

  testing::RingRobotRig& rig_;
  std::size_t cable_{0};
  bool cut_{false};
  FirstCopy first_{FirstCopy::main};
  HostHold hold_{HostHold::none};
  bool armed_{false};
};

struct InFlightRig : testing::RingRobotRig {
  FaultInFlight ring{*this};
};

std::unique_ptr<InFlightRig> ring_in_op() {
  auto rig = std::make_unique<InFlightRig>();
  testing::bring_ring_to_op(*rig, rig->ring);
  return rig;
}

// Short as SOEM counts it: a branch's counter below the plan (above it is the copies overlapping
// while a cut falls in flight: every slave still answered).
bool short_working_counter(const drivers::JointCycleResult& r, const CycleResult& master_cycle) {
  if (!r.frame_received) return true;
  for (std::size_t b = 0; b < kMaxBranches; ++b) {
    if (master_cycle.branch_wkc[b] < master_cycle.expected_wkc[b]) return true;
  }
  return false;
}

// Every cable cut and repaired in flight, the copies walked in the order `first`.
void every_cut_and_repair_in_flight(FirstCopy first, HostHold hold = HostHold::none) {
  auto rig = ring_in_op();
  ASSERT_EQ(rig->bus.master().state(), MasterState::op);
  Master& master = rig->bus.master();
  testing::cycle_and_drop_reports(*rig, kCyclesPerStep);
  drivers::JointFeedback fb{};
  drivers::JointLinkReport link_report;

  std::uint64_t cycles = 0;
  std::uint64_t short_cycles = 0;
  std::uint64_t joint_cycles_missed = 0;
  // Cycles until the armed fault fell in a cyclic exchange, then the rest of the step.
  const auto run_step = [&](std::size_t cable, const char* change) {
    for (int i = 0; i < kCyclesPerStep; ++i) {
      const drivers::JointCycleResult r = rig->cycle(fb);
      ++cycles;
      if (short_working_counter(r, rig->bus.last_cycle())) ++short_cycles;
      const JointMask missed = kAllJoints & ~r.valid;
      for (JointMask m = missed; m != 0; m &= m - 1) ++joint_cycles_missed;
      EXPECT_EQ(missed, 0U) << change << " of cable " << cable << ", cycle " << i;
    }
    EXPECT_FALSE(rig->ring.armed()) << "cable " << cable << ": the fault never fell in flight";
  };
  const std::size_t first_cable = 0;
  for (std::size_t cable = first_cable; cable <= kRingCable; ++cable) {
    rig->ring.arm(cable, true, first, hold);
    run_step(cable, "cut");
    EXPECT_EQ(master.ring_status().state, RingState::open) << "cable " << cable;
    testing::expect_one_ring_report(master, RingEventKind::opened, cable);

    rig->ring.arm(cable, false, first, hold);
    run_step(cable, "repair");
    EXPECT_EQ(master.ring_status().state, RingState::closed) << "cable " << cable;
    testing::expect_one_ring_report(master, RingEventKind::closed, cable);
    while (rig->bus.pop_report(link_report)) {
      EXPECT_NE(link_report.link.kind, LinkEventKind::lost) << "cable " << cable << ": joints " << link_report.joints;
    }
  }
  EXPECT_EQ(master.ring_status().breaks, kRingCable + 1 - first_cable);
  EXPECT_EQ(master.ring_status().repairs, kRingCable + 1 - first_cable);
  std::printf("in flight, %s copy walked first%s: %llu cycles over %zu cuts and repairs, %llu with a short working counter, %llu joint-cycles "
              "missed, %llu exchanges repeated\n",
              first == FirstCopy::main ? "main" : "ring",
              hold == HostHold::none                      ? ""
              : hold == HostHold::until_near_the_deadline ? ", copies held by the host until 80 us before the deadline"
                                                          : ", the master held 1.3 ms between its two sends", static_cast<unsigned long long>(cycles), kRingCable + 1 - first_cable,
              static_cast<unsigned long long>(short_cycles),
              static_cast<unsigned long long>(joint_cycles_missed),
              static_cast<unsigned long long>(master.link().stats().ring_repeats));
  EXPECT_EQ(short_cycles, 0U);
  EXPECT_EQ(joint_cycles_missed, 0U);
}

TEST(MasterOnTheRingWithACableChangingInFlight, EveryCutAndRepairAfterTheMainCopyLosesNoJointAndIsReportedOnce) {
  every_cut_and_repair_in_flight(FirstCopy::main);
}

TEST(MasterOnTheRingWithACableChangingInFlight, EveryCutAndRepairAfterTheRingCopyLosesNoJointAndIsReportedOnce) {
  every_cut_and_repair_in_flight(FirstCopy::ring);
}

TEST(MasterOnTheRingWithACableChangingInFlight, CopiesHeldByTheHostUntilNearTheDeadlineAfterTheMainCopyLoseNoJoint) {
  every_cut_and_repair_in_flight(FirstCopy::main, HostHold::until_near_the_deadline);
}

TEST(MasterOnTheRingWithACableChangingInFlight, CopiesHeldByTheHostUntilNearTheDeadlineAfterTheRingCopyLoseNoJoint) {
  every_cut_and_repair_in_flight(FirstCopy::ring, HostHold::until_near_the_deadline);
}

// The hold between the sends puts the main copy first: the change falls after its walk.
TEST(MasterOnTheRingWithACableChangingInFlight, MasterHeldBetweenItsTwoSendsPastTheNextPeriodLosesNoJoint) {
  every_cut_and_repair_in_flight(FirstCopy::main, HostHold::between_the_sends);
}

}  // namespace
}  // namespace rescue::ecat
