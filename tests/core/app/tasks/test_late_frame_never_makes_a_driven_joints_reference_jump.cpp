// A frame that comes back late or not at all is host jitter (a handler preempted between sending
// and its deadline) or a glitch on the wire, not a fault (docs/motion-owner.md "A late frame"). On
// the whole simulated robot in virtual time (the real EtherCAT handler and its motion intake, the
// real master, the simulated drives with their position loop and following-error check), the
// Motion owner moves both elbows at 1.2 rad/s, 1.2 rad away from where the joint manager
// initialized them, and the frames of 1, 3 or 60 periods in a row do not come back. The handler then
// has no fresh inputs of any joint: it carries each driven joint on (docs/motion-owner.md), so
//   - every driven joint's reference moves at most its velocity limit per period from the one sent
//     the period before (before the fix: it leapt back to the joint manager's reference, 1.2 rad);
//   - the drives stay in Operation enabled (before: turned towards disabled for a period), never
//     raise a following error (0x8611; before: both elbows, the CI failure of the rescue scenario),
//     and follow within a few mrad;
//   - the samples keep the elbows reachable (the RC tasks do not lock them for a late frame).
// And the handler itself held off its CPU for 60 ms while the owner goes on: the first period after
// takes the owner's reference velocity-clamped from the one sent last (no leap, no fault).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/app/tasks/motion_intake.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/simulated_firmware_rig.hpp"

namespace rescue::app {
namespace {

const std::size_t kLeft = joint_index_by_name("l_elbow");
const std::size_t kRight = joint_index_by_name("r_elbow");
constexpr double kSpeed = 1.2;  // rad/s

struct Figures {
  double largest_step{0.0};       // largest change of an elbow's reference from one period to the next
  double largest_following{0.0};  // largest |reference - actual| of an elbow at the drive, from 10 periods before the loss
  int periods_not_enabled{0};     // elbow drive periods outside Operation enabled
  int periods_unreachable{0};     // elbow samples published unreachable
  std::uint16_t error_code[2]{0, 0};
  double distance_from_init{0.0};  // how far the elbows were from the joint manager's reference
};

// `frames` frames lost from period 1000 on; or, with `stall_ms` > 0, the handler held off its CPU that
// long at period 1000 (no period runs; the owner goes on, 1 ms per period of its own).
// With `late` the frames are not lost but come back 1.5 ms late (after the next period's send: the
// handler preempted that long between sending and its deadline), and are dropped as stale.
Figures lose_frames_while_the_elbows_move(std::uint32_t frames, int stall_ms = 0, bool late = false) {
  Figures f;
  testing::TempStateDir dir;
  SimulatedFirmware fw(dir.path);
  EXPECT_TRUE(fw.start_enabled());
  const std::size_t elbows[2] = {kLeft, kRight};
  double start[2] = {fw.sample_of(kLeft).position_ref_rad, fw.sample_of(kRight).position_ref_rad};
  double last_ref[2] = {start[0], start[1]};
  MotionLinks& motion = fw.links->motion;
  const std::uint64_t word = motion.owner.take(0);
  double offset = 0.0;
  RobotSample sample{};
  for (int k = 0; k < 1600; ++k) {
    // RC task 0's period just before the handler's: both elbows, on time, 1.2 mrad further each.
    offset += kSpeed * 0.001;
    const hal::Nanoseconds now = fw.rig->bus.next_wakeup() - 100 * hal::kNsPerUs;
    ReferenceSpace& space = motion.references[0];
    space.begin();
    for (std::size_t j = 0; j < kJointCount; ++j) space.set(j, 0.0);
    for (int e = 0; e < 2; ++e) space.set(elbows[e], start[e] + offset);
    space.complete(word, space.completed() + 1, joint_bit(kLeft) | joint_bit(kRight), now);
    fw.links->rc_heartbeat_ns[0].store(now);
    if (k == 1000) {
      if (late) {
        fw.rig->segment.delay_frames(frames, 1500 * hal::kNsPerUs);
      } else {
        fw.rig->segment.drop_frames(frames);
      }
      f.distance_from_init = offset;
      for (int s = 0; s < stall_ms; ++s) {
        // The handler is stalled: the clock goes on, the owner computes every millisecond.
        fw.rig->clock.sleep_until(fw.rig->clock.now() + hal::kNsPerMs);
        offset += kSpeed * 0.001;
        space.begin();
        for (int e = 0; e < 2; ++e) space.set(elbows[e], start[e] + offset);
        space.complete(word, space.completed() + 1, joint_bit(kLeft) | joint_bit(kRight), fw.rig->clock.now());
        fw.links->rc_heartbeat_ns[0].store(fw.rig->clock.now());
      }
    }
    fw.period();
    EXPECT_TRUE(fw.links->samples.try_read(sample));
    for (int e = 0; e < 2; ++e) {
      const std::size_t j = elbows[e];
      const double ref = sample[j].position_ref_rad;
      f.largest_step = std::max(f.largest_step, std::fabs(ref - last_ref[e]));
      last_ref[e] = ref;
      const drivers::Cia402Drive& drive = fw.rig->drive(j).drive();
      if (k >= 990) f.largest_following = std::max(f.largest_following, std::fabs(ref - drive.motor().position_rad()));
      if (drive.state() != drivers::cia402::State::operation_enabled) ++f.periods_not_enabled;
      if (!sample[j].reachable) ++f.periods_unreachable;
      f.error_code[e] = std::max(f.error_code[e], drive.error_code());
    }
  }
  EXPECT_EQ(fw.handler->frames_missing(), frames) << "the frames did not come back";
  if (stall_ms > 0) {
    EXPECT_GE(fw.rig->bus.master().skipped_periods(), static_cast<std::uint64_t>(stall_ms - 1)) << "the periods were skipped";
  }
  EXPECT_EQ(fw.handler->missed_cycles(kAllJoints), 0u) << "every frame that came back brought every joint";
  return f;
}

TEST(LateFrame, ADrivenJointsReferenceNeverJumpsAndNoDriveFaults) {
  for (const std::uint32_t frames : {1u, 3u, 60u}) {
    const Figures f = lose_frames_while_the_elbows_move(frames);
    std::printf("%2u frame(s) lost with the elbows %.2f rad from their initialize reference: largest reference step "
                "%.4f rad, largest following error %.4f rad, periods not enabled %d, unreachable %d, error codes "
                "0x%04x 0x%04x\n",
                frames, f.distance_from_init, f.largest_step, f.largest_following, f.periods_not_enabled,
                f.periods_unreachable, f.error_code[0], f.error_code[1]);
    EXPECT_GT(f.distance_from_init, 1.0) << "a leap to the initialize reference would be a following error";
    EXPECT_LE(f.largest_step, kJoints[kLeft].limits.velocity_max_rad_s * 0.001 + 1e-9) << frames;
    EXPECT_LT(f.largest_following, 0.02) << frames;
    EXPECT_EQ(f.periods_not_enabled, 0) << frames;
    EXPECT_EQ(f.periods_unreachable, 0) << frames;
    EXPECT_EQ(f.error_code[0], drivers::drive_error::kNone) << frames;
    EXPECT_EQ(f.error_code[1], drivers::drive_error::kNone) << frames;
  }
}

// The CI failure's own event: one frame back late, after its deadline.
TEST(LateFrame, AFrameBackAfterItsDeadlineLeavesTheReferencesOnTheirPath) {
  const Figures f = lose_frames_while_the_elbows_move(1, 0, true);
  std::printf("1 frame back 1.5 ms late: largest reference step %.4f rad, largest following error %.4f rad, periods "
              "not enabled %d, unreachable %d, error codes 0x%04x 0x%04x\n",
              f.largest_step, f.largest_following, f.periods_not_enabled, f.periods_unreachable, f.error_code[0],
              f.error_code[1]);
  EXPECT_LE(f.largest_step, kJoints[kLeft].limits.velocity_max_rad_s * 0.001 + 1e-9);
  EXPECT_LT(f.largest_following, 0.02);
  EXPECT_EQ(f.periods_not_enabled, 0);
  EXPECT_EQ(f.periods_unreachable, 0);
  EXPECT_EQ(f.error_code[0], drivers::drive_error::kNone);
  EXPECT_EQ(f.error_code[1], drivers::drive_error::kNone);
}

// The handler itself held off its CPU for 60 ms (below the drives' 100 ms watchdog) while the owner
// goes on 72 mrad: the master skips the periods, the drives keep the last target, and the first
// period after takes the owner's reference velocity-clamped from the one sent last: no leap, no fault.
TEST(HandlerStall, TheReferenceGoesOnFromTheOneSentLastAndNoDriveFaults) {
  const Figures f = lose_frames_while_the_elbows_move(0, 60);
  std::printf("handler stalled 60 ms with the owner moving on: largest reference step %.4f rad, largest following "
              "error %.4f rad, periods not enabled %d, error codes 0x%04x 0x%04x\n",
              f.largest_step, f.largest_following, f.periods_not_enabled, f.error_code[0], f.error_code[1]);
  EXPECT_LE(f.largest_step, kJoints[kLeft].limits.velocity_max_rad_s * 0.001 + 1e-9);
  EXPECT_LT(f.largest_following, 0.1);
  EXPECT_EQ(f.periods_not_enabled, 0);
  EXPECT_EQ(f.error_code[0], drivers::drive_error::kNone);
  EXPECT_EQ(f.error_code[1], drivers::drive_error::kNone);
}

}  // namespace
}  // namespace rescue::app
