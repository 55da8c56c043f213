// RunControl is a record of the shared segment the supervisor reads to stop the tasks and to print
// and judge the run's figures (core/app/runtime/run_control_check.hpp). A value no writer writes is
// damage and is named: a flag byte other than 0 or 1, a negative count of tasks started, a joint
// mask beyond the robot, a robot condition or ring state that does not exist, a silent task beyond
// the slots, a sent figure that is not a finite number >= 0 (a NaN passed the joint-limit verdict as
// "within"). Whole values of every kind, the largest counts included, are not damage.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <memory>
#include <string>

#include "core/app/runtime/run_control_check.hpp"
#include "ecat/master/ring_monitor.hpp"
#include "fsm/machines/joint_status_dfa.hpp"

namespace rescue::app {
namespace {

constexpr int kTasks = 6;

std::string damage(const RunControl& run) {
  const char* field = run_control_damage(run);
  return field != nullptr ? field : "none";
}

void set_flag_byte(std::atomic<bool>& flag, unsigned char byte) { std::memcpy(static_cast<void*>(&flag), &byte, 1); }

TEST(RunControlCheck, WholeValuesOfEveryKindAreNotDamage) {
  const std::unique_ptr<RunControl> run = std::make_unique<RunControl>();
  EXPECT_EQ(damage(*run), "none");
  run->stop.store(true);
  run->op.store(true);
  run->tasks_started.store(kTasks + 3);  // restarted task processes count again
  run->lost_joints.store(kAllJoints);
  run->lost_since_start.store(kAllJoints);
  run->condition.store(static_cast<std::uint8_t>(fsm::RobotCondition::error));
  run->ring_state.store(static_cast<std::uint8_t>(ecat::RingState::lost));
  run->silent_tasks.store((1U << kRunHealthSlots) - 1);
  run->cycles.store(std::numeric_limits<std::uint64_t>::max());
  run->sent_max_jerk_rad_s3[0].store(1e9);
  run->health[0].reported.store(true);
  EXPECT_EQ(damage(*run), "none");
}

TEST(RunControlCheck, AFlagByteOtherThanZeroOrOneIsNamed) {
  const std::unique_ptr<RunControl> run = std::make_unique<RunControl>();
  set_flag_byte(run->manager_done, 0x80);
  EXPECT_EQ(damage(*run), "RunControl::manager_done");
  set_flag_byte(run->manager_done, 1);
  set_flag_byte(run->stop, 2);
  EXPECT_EQ(damage(*run), "RunControl::stop");
  set_flag_byte(run->stop, 0);
  set_flag_byte(run->health[3].reported, 0xFF);
  EXPECT_EQ(damage(*run), "RunControl::health[].reported");
}

TEST(RunControlCheck, ValuesBeyondTheirRangeAreNamed) {
  struct Case {
    void (*damage)(RunControl&);
    const char* field;
  };
  const Case cases[] = {
      {[](RunControl& r) { r.tasks_started.store(-1); }, "RunControl::tasks_started"},
      {[](RunControl& r) { r.lost_joints.store(JointMask{1} << kJointCount); }, "RunControl::lost_joints"},
      {[](RunControl& r) { r.lost_since_start.store(0x80000000U); }, "RunControl::lost_since_start"},
      {[](RunControl& r) { r.condition.store(static_cast<std::uint8_t>(fsm::RobotCondition::error) + 1); },
       "RunControl::condition"},
      {[](RunControl& r) { r.ring_state.store(0xFF); }, "RunControl::ring_state"},
      {[](RunControl& r) { r.silent_tasks.store(1U << kRunHealthSlots); }, "RunControl::silent_tasks"},
      {[](RunControl& r) { r.sent_max_speed_rad_s[4].store(std::numeric_limits<double>::quiet_NaN()); },
       "RunControl::sent_max_speed_rad_s"},
      {[](RunControl& r) { r.sent_max_acceleration_rad_s2[0].store(-1.0); }, "RunControl::sent_max_acceleration_rad_s2"},
      {[](RunControl& r) { r.sent_max_jerk_rad_s3[20].store(std::numeric_limits<double>::infinity()); },
       "RunControl::sent_max_jerk_rad_s3"},
  };
  for (const Case& c : cases) {
    const std::unique_ptr<RunControl> run = std::make_unique<RunControl>();
    c.damage(*run);
    EXPECT_EQ(damage(*run), c.field);
  }
}

}  // namespace
}  // namespace rescue::app
