// While the simulated robot runs in OP: a drive fault reaches the master as a CiA 402 fault in
// that joint's inputs (statusword, error code) without disturbing the exchange or being taken for a
// lost link, and is cleared with a fault reset; CoE SDO transfers (joint limits, modes) complete
// through the cyclic frame, one mailbox step per cycle, with every joint valid in every cycle.
#include <gtest/gtest.h>

#include <memory>

#include "drivers/cia402/cia402_enable.hpp"
#include "tests/support/simulated_robot_rig.hpp"
#include "drivers/joint/joint_units.hpp"

namespace rescue::ecat {
namespace {

using testing::SimulatedRobotRig;

class RunningRobot : public ::testing::Test {
 protected:
  void SetUp() override {
    rig = std::make_unique<SimulatedRobotRig>();
    ASSERT_TRUE(rig->bus.bring_up(testing::fast_options()).ok()) << testing::describe_master_failure(rig->bus.master());
    for (int i = 0; i < 200 && rig->bus.master().state() != MasterState::op; ++i) (void)cycle();
    ASSERT_EQ(rig->bus.master().state(), MasterState::op);
    (void)cycle();
    for (std::size_t j = 0; j < kJointCount; ++j) {
      refs[j].mode_of_operation = static_cast<std::int8_t>(kJoints[j].default_mode);
      refs[j].target_position = fb.joints[j].position_actual;
    }
    // The drives finish their power-up self test, then take 3 cycles to enable.
    for (int i = 0; i < 100 && fb.valid == kAllJoints && !all_enabled(); ++i) (void)enable_step();
    for (std::size_t j = 0; j < kJointCount; ++j) ASSERT_TRUE(drivers::is_enabled(fb.joints[j].statusword)) << kJoints[j].name;
  }
  drivers::JointCycleResult cycle() { return rig->cycle(refs, fb); }
  bool all_enabled() const {
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if (!drivers::is_enabled(fb.joints[j].statusword)) return false;
    }
    return true;
  }
  drivers::JointCycleResult enable_step() {
    for (std::size_t j = 0; j < kJointCount; ++j) refs[j].controlword = drivers::controlword_towards_enabled(fb.joints[j].statusword, refs[j].controlword);
    return cycle();
  }

  std::unique_ptr<SimulatedRobotRig> rig;
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
};

TEST_F(RunningRobot, DriveFaultArrivesAsInputsAndIsReset) {
  const std::size_t elbow = joint_index_by_name("l_elbow");
  rig->drive(elbow).drive().inject_fault(0x2310, false);  // over-current, cause gone at once
  bool seen = false;
  for (int i = 0; i < 20; ++i) {
    const drivers::JointCycleResult r = cycle();
    EXPECT_EQ(r.valid, kAllJoints) << "a drive fault is not a lost link";
    if (drivers::is_faulted(fb.joints[elbow].statusword)) {
      seen = true;
      EXPECT_EQ(fb.joints[elbow].error_code, 0x2310);
    }
  }
  EXPECT_TRUE(seen);
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if (j != elbow) {
      EXPECT_TRUE(drivers::is_enabled(fb.joints[j].statusword)) << kJoints[j].name;
    }
  }
  LinkReport report;
  EXPECT_FALSE(rig->bus.master().pop_report(report));

  refs[elbow].target_position = fb.joints[elbow].position_actual;  // hold where it stopped
  for (int i = 0; i < 10; ++i) (void)enable_step();
  EXPECT_TRUE(drivers::is_enabled(fb.joints[elbow].statusword));
}

TEST_F(RunningRobot, PersistentFaultCannotBeReset) {
  const std::size_t track = joint_index_by_name("r_track");
  rig->drive(track).drive().inject_fault(0x4310, true);  // over-temperature that stays
  for (int i = 0; i < 20; ++i) (void)enable_step();
  EXPECT_TRUE(drivers::is_faulted(fb.joints[track].statusword));
  EXPECT_EQ(fb.joints[track].error_code, 0x4310);
  rig->drive(track).drive().clear_fault_cause();
  refs[track].target_velocity = 0;
  for (int i = 0; i < 10; ++i) (void)enable_step();
  EXPECT_TRUE(drivers::is_enabled(fb.joints[track].statusword));
}

TEST_F(RunningRobot, SdoRoundTripsThroughTheCyclicFrame) {
  MailboxClient& mailbox = rig->bus.master().mailbox();
  const auto neck = static_cast<std::uint8_t>(slave_position_of_joint(joint_index_by_name("neck_pan")));
  ASSERT_TRUE(mailbox.submit(sdo_download(neck, 0x6072, 0, 640, 2, 1)));   // max torque 64 %
  ASSERT_TRUE(mailbox.submit(sdo_upload(neck, 0x6072, 0, 2)));
  ASSERT_TRUE(mailbox.submit(sdo_upload(neck, 0x1018, 1, 3)));             // identity: vendor id
  ASSERT_TRUE(mailbox.submit(sdo_download(neck, 0x6072, 0, 5000, 2, 4)));  // out of range
  ASSERT_TRUE(mailbox.submit(sdo_upload(neck, 0x5FFF, 0, 5)));             // no such object
  std::vector<SdoCompletion> done;
  for (int i = 0; i < 200 && done.size() < 5; ++i) {
    const drivers::JointCycleResult r = cycle();
    EXPECT_EQ(r.valid, kAllJoints) << "the mailbox never costs a cycle";
    SdoCompletion c;
    while (mailbox.pop_completion(c)) done.push_back(c);
  }
  ASSERT_EQ(done.size(), 5u);
  EXPECT_EQ(done[0].outcome, SdoOutcome::ok);
  EXPECT_EQ(done[1].outcome, SdoOutcome::ok);
  EXPECT_EQ(sdo_value(done[1]), 640u);
  EXPECT_EQ(done[2].outcome, SdoOutcome::ok);
  EXPECT_EQ(sdo_value(done[2]), drivers::kRescueVendorId);
  EXPECT_EQ(done[3].outcome, SdoOutcome::aborted);
  EXPECT_EQ(done[3].abort_code, 0x06090031u);  // value too high
  EXPECT_EQ(done[4].outcome, SdoOutcome::aborted);
  EXPECT_EQ(done[4].abort_code, 0x06020000u);  // object does not exist
  for (const SdoCompletion& c : done) EXPECT_LE(c.exchanges, 10u) << c.request.tag;
}

TEST_F(RunningRobot, JointLimitsWrittenAtRuntime) {
  const std::size_t elbow = joint_index_by_name("r_elbow");
  JointLimits tighter = kJoints[elbow].limits;
  tighter.position_max_rad = 1.0;
  tighter.torque_max_nm = 40.0;
  ASSERT_TRUE(rig->bus.request_limits(elbow, tighter, 77));
  MailboxClient& mailbox = rig->bus.master().mailbox();
  std::vector<SdoCompletion> done;
  for (int i = 0; i < 200 && done.size() < drivers::kLimitSdosPerJoint; ++i) {
    (void)cycle();
    SdoCompletion c;
    while (mailbox.pop_completion(c)) done.push_back(c);
  }
  ASSERT_EQ(done.size(), drivers::kLimitSdosPerJoint);
  for (const SdoCompletion& c : done) {
    EXPECT_EQ(c.outcome, SdoOutcome::ok) << std::hex << c.request.index << " " << c.abort_code;
    EXPECT_EQ(c.request.tag, 77u);
  }
  EXPECT_EQ(rig->drive(elbow).objects().od().get_i32(0x607D, 2), drivers::rad_to_counts(1.0));
  EXPECT_EQ(rig->drive(elbow).objects().od().get_u32(0x6072, 0), 500u);  // 40 of 80 Nm
}

}  // namespace
}  // namespace rescue::ecat
