// Over two veth pairs against `rescue-motion sim --iface A --ring-iface B` (the robot's ring
// configuration; wall clock, raw sockets, 1 ms period): the master with both ports (the ring plan,
// docs/redundancy.md), every drive enabled and moving, while cables are cut and restored one at a
// time through the simulator's console, the fault falling wherever the simulator is (between two
// frames, or between the two copies of one frame). For each cable: no joint is lost, the break is
// reported once with its place and the repair once, and a cycle misses a joint only when a copy came
// back late (host jitter on a loaded machine, counted apart). The clocks across each break are
// measured as the virtual-time test (test_ring_keeps_every_clock_synchronised_across_any_single_cut)
// measures them, here on the wall clock: max |0x092C| read by the master (cyclic FPRD, one slave at
// a time) from 100 ms after the cut to the repair and after the repair, and the largest move of a
// drive's SYNC0 edge from the simulator's true clock offsets (its console's `clocks`), sampled six
// times in each half. Two cuts lose exactly the slaves between them, and both repaired bring them back.
//
// The DC figures are held to issue 34's bounds (max |0x092C| behind the break at most 100 ns from
// 100 ms after the cut, no SYNC0 edge moved by more than 1 us), and after the repairs to the same
// 100 ns and 1 us: the island (docs/redundancy.md "DC method") takes the time behind a break within
// the ring copy, so no host delay between the copies enters it, and its reference is not steered from
// copies as noisy as veth's.
#include <gtest/gtest.h>

#include <signal.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/base/endian.hpp"
#include "drivers/cia402/cia402_enable.hpp"
#include "ecat/codec/registers.hpp"
#include "tests/support/master_over_veth.hpp"
#include "tests/support/ring_robot_rig.hpp"

namespace rescue::app {
namespace {

constexpr int kCyclesPerStep = 300;     // each cut, and each repair
constexpr std::uint32_t kBreakDifferenceBoundNs = 100;  // issue 34 item 3
constexpr std::int64_t kSync0MoveBoundNs = 1000;
constexpr int kSettleCycles = 100;      // the DC figures are read from 100 ms after the cut (issue 34 item 3)
constexpr int kClockSampleEvery = 50;   // the simulator's true offsets, six times a step
constexpr std::int32_t kMoveAmplitudeCounts = 2000;  // every joint's target: +-2000 counts (~12 mrad) about its start
constexpr int kMovePeriodCycles = 2000;              // a 2 s sine

std::string hex(std::uint64_t v) {
  char text[20];
  (void)std::snprintf(text, sizeof text, "%llx", static_cast<unsigned long long>(v));
  return text;
}

class RingOverVeth : public rescue::testing::MasterOverVethTest {
 protected:
  bool ring() const override { return true; }
};

struct Cable {
  std::string name;   // the fault console's name: the slave the cable leads into, or "ring"
  std::size_t cable;  // position (the cable into its port 0), or testing::kRingCable
};

std::vector<Cable> cables_to_cut() {
  std::vector<Cable> all;
  for (std::size_t p = 0; p < kSlaveCount; ++p) all.push_back({drivers::kRobotRingNetworkPlan[p].name, p});
  all.push_back({"ring", rescue::testing::kRingCable});
  return all;
}

using Offsets = std::array<std::int64_t, kSlaveCount>;

// What one half (the break, or the repair) did to the clocks.
struct ClockFigures {
  std::uint32_t max_difference{0};         // max |0x092C| read from kSettleCycles on
  std::uint32_t max_difference_behind{0};  // ... of the slaves behind the break
  int difference_reads{0};                 // 0x092C reads answered
  std::vector<int> clock_tags;             // the simulator's true offsets asked during the half
  std::int64_t sync0_moved{0};             // largest move of a drive's SYNC0 edge against the cut's instant
  int clock_samples{0};                    // ... over this many of them answered
  std::string beyond;                      // each read over kBreakDifferenceBoundNs: slave, cycle, value
};

class RingCuts : public RingOverVeth {
 protected:
  // Asks the simulator for its true clock offsets; the answer is read by offsets_of(tag) later.
  int ask_clocks(const std::string& before = "") {
    const int tag = ++clock_tag_;
    EXPECT_TRUE(sim_.write_input("clocks " + std::to_string(tag) + "\n" + before));
    return tag;
  }
  bool offsets_of(int tag, Offsets& out) {
    const std::string key = "clocks " + std::to_string(tag) + ":";
    if (!sim_.wait_for_output(key, kStartTimeoutMs)) return false;
    const std::string& text = sim_.output();
    const char* p = text.c_str() + text.find(key) + key.size();
    for (std::int64_t& o : out) {
      char* end = nullptr;
      o = std::strtoll(p, &end, 10);
      if (end == p) return false;
      p = end;
    }
    return true;
  }

  // One cycle with the robot moving: every joint's target a sine about where it was enabled.
  drivers::JointCycleResult moving_cycle() {
    const double phase = 2.0 * 3.14159265358979 * static_cast<double>(move_cycle_++ % kMovePeriodCycles) / kMovePeriodCycles;
    for (std::size_t j = 0; j < kJointCount; ++j) {
      refs_[j].target_position = hold_[j] + static_cast<std::int32_t>(kMoveAmplitudeCounts * std::sin(phase));
    }
    const ecat::LinkStats before = bus_->master().link().stats();
    const drivers::JointCycleResult r = cycle();
    const ecat::LinkStats& after = bus_->master().link().stats();
    const bool late = !r.frame_received || after.timeouts != before.timeouts || after.stale_frames != before.stale_frames;
    const JointMask missed = kAllJoints & ~r.valid;
    ++cycles_;
    // A copy the exchange did not wait for (it did not come back last time: a cut at a master
    // port) that turned up after the exchange ended is stale in the next one: the miss it caused
    // was a late copy too.
    if (after.stale_frames != before.stale_frames && previous_miss_unexplained_) {
      --missed_without_a_late_copy_;
      ++cycles_with_a_late_copy_;
    }
    previous_miss_unexplained_ = missed != 0 && !late;
    cycles_with_a_late_copy_ += late ? 1 : 0;
    cycles_missed_ += missed != 0 ? 1 : 0;
    missed_without_a_late_copy_ += missed != 0 && !late ? 1 : 0;
    joint_cycles_missed_ += ecat::popcount(missed);
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if ((r.valid & joint_bit(j)) == 0) continue;
      lowest_[j] = std::min(lowest_[j], feedback_.joints[j].position_actual);
      highest_[j] = std::max(highest_[j], feedback_.joints[j].position_actual);
    }
    return r;
  }

  // Every drive enabled in cyclic position mode, its start position kept.
  void enable_every_drive() {
    for (int i = 0; i < 300; ++i) {
      rescue::testing::enable_every_drive_step(refs_, feedback_);
      (void)cycle();
    }
    for (std::size_t j = 0; j < kJointCount; ++j) {
      ASSERT_TRUE(drivers::is_enabled(feedback_.joints[j].statusword)) << kJoints[j].name;
      hold_[j] = feedback_.joints[j].position_actual;
      lowest_[j] = hold_[j];
      highest_[j] = hold_[j];
    }
  }

  // kCyclesPerStep moving cycles: the 0x092C figures of that half, and its clock samples asked.
  // `behind_from`: the first position behind the break (kSlaveCount: none).
  // One register read is in flight at a time, and it can outlive the half that asked it (a late
  // copy sends it again next frame): it is then taken in the next half and its figure dropped, as
  // it belongs to the other half. Left untaken, the master would refuse every later read.
  ClockFigures run_step(std::size_t behind_from) {
    ClockFigures f;
    ecat::Master& master = bus_->master();
    ++step_;
    for (int i = 0; i < kCyclesPerStep; ++i) {
      if (i % kClockSampleEvery == kClockSampleEvery - 1) f.clock_tags.push_back(ask_clocks());
      if (i >= kSettleCycles && !reading_) {
        reading_ = master.request_register_read(next_read_, ecat::reg::kDcSystemTimeDifference, 4);
        read_step_ = step_;
      }
      (void)moving_cycle();
      ecat::RegisterReadResult read;
      if (reading_ && master.take_register_read(read)) {
        reading_ = false;
        if (read.status == ecat::RegisterReadStatus::ok && read_step_ == step_) {
          const std::uint32_t difference = load_le32(read.data.data()) & 0x7FFFFFFFU;
          ++f.difference_reads;
          f.max_difference = std::max(f.max_difference, difference);
          if (difference > kBreakDifferenceBoundNs) {
            // Which slave, when, and whether copies came back late: what explains a figure over the bound.
            const ecat::RingDcStatus& dc = master.ring_dc_status();
            f.beyond += " [slave " + std::to_string(read.position) + " at cycle " + std::to_string(i) + ": " +
                        std::to_string(difference) + " ns, " + std::to_string(cycles_with_a_late_copy_) +
                        " late-copy cycles so far, restores skipped " + std::to_string(dc.restores_skipped) +
                        ", ways set 0x" + hex(dc.ways_set) + "]";
          }
          if (read.position >= behind_from) f.max_difference_behind = std::max(f.max_difference_behind, difference);
        }
        next_read_ = (next_read_ + 1) % kSlaveCount;
      }
    }
    return f;
  }
  // The largest move of a drive's SYNC0 edge in the half's samples, against `before`.
  void measure_sync0(ClockFigures& f, const Offsets& before) {
    for (const int tag : f.clock_tags) {
      Offsets now{};
      if (!offsets_of(tag, now)) continue;
      ++f.clock_samples;
      for (std::size_t p = 0; p < kSlaveCount; ++p) {
        if (kSlaves[p].kind == SlaveKind::joint_drive) f.sync0_moved = std::max(f.sync0_moved, std::abs(now[p] - before[p]));
      }
    }
  }

  int clock_tag_{0};
  int step_{0};                 // halves run so far
  bool reading_{false};         // a register read asked and not yet taken
  int read_step_{0};            // ... asked in this half
  std::size_t next_read_{0};    // the slave whose 0x092C is read next
  std::uint64_t move_cycle_{0};
  std::array<std::int32_t, kJointCount> hold_{};
  std::array<std::int32_t, kJointCount> lowest_{};
  std::array<std::int32_t, kJointCount> highest_{};
  int cycles_{0};
  int joint_cycles_missed_{0};
  int cycles_missed_{0};
  int cycles_with_a_late_copy_{0};
  int missed_without_a_late_copy_{0};
  bool previous_miss_unexplained_{false};
};

ecat::MasterOptions veth_options() {
  ecat::MasterOptions options;
  options.drift_compensation_frames = 3000;
  options.frame_timeout = 20 * hal::kNsPerMs;
  return options;
}

void drop_ring_reports(ecat::Master& master) {
  ecat::RingReport dropped;
  while (master.pop_ring_report(dropped)) {
  }
}

TEST_F(RingCuts, CuttingEveryCableOneAtATimeLosesNoJointKeepsTheClocksAndReportsEachBreakAndRepairOnce) {
  bring_up_to_op(veth_options(), 3000);
  if (HasFatalFailure()) return;
  ecat::Master& master = bus_->master();
  ASSERT_EQ(master.ring_status().state, ecat::RingState::closed);
  enable_every_drive();
  if (HasFatalFailure()) return;
  for (int i = 0; i < 100; ++i) (void)moving_cycle();
  drop_ring_reports(master);
  reports_.clear();

  const std::vector<Cable> cables = cables_to_cut();
  ClockFigures worst;
  ClockFigures worst_repair;
  for (const Cable& c : cables) {
    // The offsets at the cut's instant: the simulator answers `clocks` just before it applies the cut.
    const int unexplained_before = missed_without_a_late_copy_;
    const int at_cut = ask_clocks("cut " + c.name + "\n");
    ClockFigures broken = run_step(c.cable < kSlaveCount ? c.cable : kSlaveCount);
    EXPECT_TRUE(sim_.wait_for_output("fault: ok cut " + c.name, kStartTimeoutMs)) << sim_.output();
    EXPECT_EQ(master.ring_status().state, ecat::RingState::open) << c.name;
    rescue::testing::expect_one_ring_report(master, ecat::RingEventKind::opened, c.cable);
    const ecat::RingDcStatus dc = master.ring_dc_status();
    ASSERT_TRUE(sim_.write_input("restore " + c.name + "\n"));
    const int late_before_repair = cycles_with_a_late_copy_;
    ClockFigures repaired = run_step(kSlaveCount);
    EXPECT_TRUE(sim_.wait_for_output("fault: ok restore " + c.name, kStartTimeoutMs)) << sim_.output();
    EXPECT_EQ(master.ring_status().state, ecat::RingState::closed) << c.name;
    rescue::testing::expect_one_ring_report(master, ecat::RingEventKind::closed, c.cable);
    Offsets before{};
    ASSERT_TRUE(offsets_of(at_cut, before)) << sim_.output();
    measure_sync0(broken, before);
    measure_sync0(repaired, before);
    std::printf("cable %2zu %-16s: after break max |0x092C| %u ns behind it (%u ns any; %d reads), SYNC0 moved %lld ns (%d "
                "samples), %llu slaves in the island (steered %lld ns in %llu steps, noise %lld ns, %llu baselines again); after repair max "
                "|0x092C| %u ns, SYNC0 moved %lld ns; %d cycles missed a joint without a late copy\n",
                c.cable, c.name.c_str(), broken.max_difference_behind, broken.max_difference, broken.difference_reads,
                static_cast<long long>(broken.sync0_moved), broken.clock_samples,
                static_cast<unsigned long long>(ecat::popcount(dc.written)), static_cast<long long>(dc.steered_ns),
                static_cast<unsigned long long>(dc.steps), static_cast<long long>(dc.noise_ns),
                static_cast<unsigned long long>(dc.rebaselines), repaired.max_difference,
                static_cast<long long>(repaired.sync0_moved), missed_without_a_late_copy_ - unexplained_before);
    if (!broken.beyond.empty() || !repaired.beyond.empty()) {
      std::printf("  over %u ns: break%s; repair (from %d late-copy cycles)%s\n", kBreakDifferenceBoundNs,
                  broken.beyond.c_str(), late_before_repair, repaired.beyond.c_str());
    }
    EXPECT_GE(broken.difference_reads, static_cast<int>(kSlaveCount)) << c.name << ": every slave's 0x092C read in the break";
    EXPECT_EQ(broken.clock_samples, kCyclesPerStep / kClockSampleEvery) << c.name;
    worst.max_difference_behind = std::max(worst.max_difference_behind, broken.max_difference_behind);
    worst.max_difference = std::max(worst.max_difference, broken.max_difference);
    worst.sync0_moved = std::max(worst.sync0_moved, broken.sync0_moved);
    worst_repair.max_difference = std::max(worst_repair.max_difference, repaired.max_difference);
    worst_repair.sync0_moved = std::max(worst_repair.sync0_moved, repaired.sync0_moved);
  }
  EXPECT_EQ(reported(ecat::LinkEventKind::lost), 0U) << "no joint lost to a single cut";
  EXPECT_EQ(master.ring_status().breaks, cables.size());
  EXPECT_EQ(master.ring_status().repairs, cables.size());
  EXPECT_EQ(missed_without_a_late_copy_, 0) << "a joint missed a cycle whose copies all came back in time";
  // Every joint moved (half the sine's swing at least: a joint that starts at a limit follows one half).
  for (std::size_t j = 0; j < kJointCount; ++j) {
    EXPECT_GE(highest_[j] - lowest_[j], kMoveAmplitudeCounts / 2) << kJoints[j].name << " did not move";
  }
  std::printf("ring over veth: %d cycles over %zu cuts and repairs: %d cycles missed a joint (%d joint-cycles), %d cycles with "
              "a late copy, %llu exchanges repeated, %llu transients\n",
              cycles_, cables.size(), cycles_missed_, joint_cycles_missed_, cycles_with_a_late_copy_,
              static_cast<unsigned long long>(master.link().stats().ring_repeats),
              static_cast<unsigned long long>(master.ring_status().transients));
  std::printf("ring over veth, DC: after a break max |0x092C| %u ns behind it (%u ns any slave), SYNC0 moved at most %lld ns; "
              "after the repairs max |0x092C| %u ns, SYNC0 moved at most %lld ns\n",
              worst.max_difference_behind, worst.max_difference, static_cast<long long>(worst.sync0_moved),
              worst_repair.max_difference, static_cast<long long>(worst_repair.sync0_moved));
  EXPECT_LE(worst.max_difference_behind, kBreakDifferenceBoundNs) << "issue 34: max |0x092C| behind a break";
  EXPECT_LE(worst.sync0_moved, kSync0MoveBoundNs) << "issue 34: a drive's SYNC0 edge moved across a break";
  EXPECT_LE(worst_repair.max_difference, kBreakDifferenceBoundNs) << "max |0x092C| after a repair";
  EXPECT_LE(worst_repair.sync0_moved, kSync0MoveBoundNs) << "a drive's SYNC0 edge moved after a repair";
  for (const bool ring_port : {false, true}) {
    const ecat::StampedPort::SendDurations& d = master.send_durations(ring_port);
    std::printf("ring over veth, master's %s port: %llu sends, %llu took over 5 us, %llu over 20 us, the longest %lld ns\n",
                ring_port ? "ring" : "main", static_cast<unsigned long long>(d.sends),
                static_cast<unsigned long long>(d.over_5us), static_cast<unsigned long long>(d.over_20us),
                static_cast<long long>(d.max));
  }
  EXPECT_EQ(sim_.stop(SIGTERM), 0) << sim_.output();
  // The simulator's figures of the two copies: how far apart they were sent, how late it read them.
  const std::string& served = sim_.output();
  const std::size_t spacing = served.find("copy spacing:");
  EXPECT_NE(spacing, std::string::npos) << served;
  if (spacing != std::string::npos) {
    std::printf("ring over veth, simulator: %s\n", served.substr(spacing, served.find('\n', spacing) - spacing).c_str());
  }
  // Frames the host read after the simulator had moved past their arrival (docs/hal.md).
  const std::size_t late = served.find("frames taken late:");
  EXPECT_NE(late, std::string::npos) << served;
  if (late != std::string::npos) {
    std::printf("ring over veth, simulator: %s\n", served.substr(late, served.find('\n', late) - late).c_str());
  }
}

// Two cuts (the cables into l_leg and neck_pan) lose exactly the slaves between them, 9 .. 13: the ring
// `lost`, those five unreachable and reported lost, every other joint valid; both repaired, the ring
// closes, the five are reported restored and, re-integrated, every joint is valid again.
TEST_F(RingCuts, TwoCutsLoseExactlyTheSlavesBetweenThemAndBothRepairedBringThemBack) {
  bring_up_to_op(veth_options(), 3000);
  if (HasFatalFailure()) return;
  ecat::Master& master = bus_->master();
  enable_every_drive();
  if (HasFatalFailure()) return;
  for (int i = 0; i < 100; ++i) (void)moving_cycle();
  drop_ring_reports(master);
  reports_.clear();
  constexpr std::size_t kFirst = 9;    // l_leg
  constexpr std::size_t kSecond = 14;  // neck_pan
  ecat::SlaveMask between = 0;
  for (std::size_t p = kFirst; p < kSecond; ++p) between |= ecat::slave_bit(p);
  const JointMask lost_joints = drivers::joints_of_slaves(between);
  ASSERT_TRUE(sim_.write_input("cut l_leg\ncut neck_pan\n"));
  // The last cycle whose copies all came back in time tells what the master keeps.
  JointMask valid_in_time = 0;
  for (int i = 0; i < kCyclesPerStep; ++i) {
    const int late_before = cycles_with_a_late_copy_;
    const drivers::JointCycleResult r = moving_cycle();
    if (cycles_with_a_late_copy_ == late_before) valid_in_time = r.valid;
  }
  EXPECT_TRUE(sim_.wait_for_output("fault: ok cut neck_pan", kStartTimeoutMs)) << sim_.output();
  EXPECT_EQ(master.ring_status().state, ecat::RingState::lost);
  EXPECT_EQ(master.ring_status().unreachable, between);
  EXPECT_EQ(valid_in_time, kAllJoints & ~lost_joints);
  EXPECT_EQ(reported(ecat::LinkEventKind::lost), lost_joints);

  ASSERT_TRUE(sim_.write_input("restore l_leg\nrestore neck_pan\n"));
  JointMask to_reintegrate = 0;
  for (int i = 0; i < 5000 && (valid_in_time != kAllJoints || i < kCyclesPerStep); ++i) {
    const int late_before = cycles_with_a_late_copy_;
    const std::size_t seen = reports_.size();
    const drivers::JointCycleResult r = moving_cycle();
    if (cycles_with_a_late_copy_ == late_before) valid_in_time = r.valid;
    for (std::size_t k = seen; k < reports_.size(); ++k) {
      if (reports_[k].link.kind == ecat::LinkEventKind::restored) to_reintegrate |= reports_[k].joints;
    }
    if (to_reintegrate != 0 && bus_->reintegrate(to_reintegrate)) to_reintegrate = 0;
  }
  EXPECT_EQ(reported(ecat::LinkEventKind::restored), lost_joints);
  EXPECT_EQ(master.ring_status().state, ecat::RingState::closed);
  EXPECT_EQ(valid_in_time, kAllJoints);
  std::printf("ring over veth, two cuts: %d cycles, %d with a late copy\n", cycles_, cycles_with_a_late_copy_);
  EXPECT_EQ(sim_.stop(SIGTERM), 0) << sim_.output();
}

}  // namespace
}  // namespace rescue::app
