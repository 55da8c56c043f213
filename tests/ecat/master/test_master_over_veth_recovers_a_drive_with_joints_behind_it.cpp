// Over a veth pair against `rescue-motion sim --iface` (wall clock, raw socket, 1 ms period), with
// online recovery: a drive with joints behind it (r_leg: l_track and r_track behind; neck_pan:
// neck_tilt behind) switched off through the simulator's fault console for 300 ms and on again.
// Every joint behind it is reported lost with it, and all of them come back to OP by themselves
// (the drive blank, those behind it addressed but stopped by their watchdogs); the other branches
// lose no joint (a frame late on a loaded test machine is tolerated, a report never).
#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <cstdio>

#include "tests/support/master_over_veth.hpp"

namespace rescue::app {
namespace {

using MasterOverVeth = rescue::testing::MasterOverVethTest;

JointMask branches_of(JointMask joints) {
  JointMask mask = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((joints & joint_bit(j)) != 0) mask |= joints_of_branch(kJoints[j].branch);
  }
  return mask;
}

TEST_F(MasterOverVeth, RecoversADriveSwitchedOffWithJointsBehindIt) {
  ecat::MasterOptions options;
  options.drift_compensation_frames = 3000;
  options.frame_timeout = 20 * hal::kNsPerMs;
  options.online_recovery = true;
  bring_up_to_op(options, 3000);
  if (HasFatalFailure()) return;
  for (const char* drive : {"r_leg", "neck_pan"}) {
    const std::size_t joint = joint_index_by_name(drive);
    const JointMask gone = joints_lost_by_link_failure_at(joint);
    ASSERT_GT(ecat::popcount(gone), 1) << drive;
    const JointMask untouched = kAllJoints & ~branches_of(gone);
    reports_.clear();
    ASSERT_TRUE(sim_.write_input(std::string("power-off ") + drive + "\n"));
    int late = 0;     // frames not back in their period: host jitter
    int damaged = 0;  // frames back in their period without every joint of another branch: a fault
    const auto count = [&](const drivers::JointCycleResult& r) {
      if (!r.frame_received) {
        ++late;
      } else if ((r.valid & untouched) != untouched) {
        ++damaged;
      }
    };
    for (int i = 0; i < 300; ++i) count(cycle());
    EXPECT_EQ(reported(ecat::LinkEventKind::lost), gone) << drive;
    ASSERT_TRUE(sim_.write_input(std::string("power-on ") + drive + "\n"));
    int periods = 0;
    for (; periods < 10000 && (reported(ecat::LinkEventKind::recovered) & gone) != gone; ++periods) {
      count(cycle());
    }
    EXPECT_EQ(reported(ecat::LinkEventKind::recovered) & gone, gone) << drive << ": every joint behind it recovered";
    int all_valid = 0;
    int back_short = 0;  // frames back in their period without every joint, after the recovery
    for (int i = 0; i < 200; ++i) {
      const drivers::JointCycleResult r = cycle();
      all_valid += r.valid == kAllJoints ? 1 : 0;
      back_short += r.frame_received && r.valid != kAllJoints ? 1 : 0;
    }
    EXPECT_GT(all_valid, 0) << drive << ": every joint exchanged again";
    EXPECT_EQ(back_short, 0) << drive << ": a frame back in its period without every joint after the recovery";
    EXPECT_EQ((reported(ecat::LinkEventKind::lost) | reported(ecat::LinkEventKind::not_operational)) & untouched, 0u)
        << "no joint of another branch lost";
    EXPECT_EQ(damaged, 0) << drive << ": a frame back in its period without every joint of another branch";
    std::printf("veth, 1 ms: %s off 300 ms, on: %d joints back in OP %d periods after power-on; other branches: %d frames "
                "back without them, %d periods without a frame (host jitter)\n",
                drive, ecat::popcount(gone), periods, damaged, late);
  }
  EXPECT_EQ(sim_.stop(SIGTERM), 0) << sim_.output();
}

}  // namespace
}  // namespace rescue::app
