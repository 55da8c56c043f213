// The reconfiguration procedure (paper IV-C, design brief section 6) end to end on virtual time: a fake
// EtherCAT handler (1 ms cycles, LostJointTracker, limit check) and the real joint manager with the real
// error-joints file in a temporary state directory. The link into l_elbow is cut after one second.
#include <gtest/gtest.h>

#include "core/app/tasks/lost_joint_tracker.hpp"
#include "core/app/tasks/predefined_messages.hpp"
#include "drivers/joint/joint_units.hpp"
#include "tests/support/joint_manager_fakes.hpp"

namespace rescue::app {
namespace {

using fsm::JointInput;
using fsm::JointState;
using testing::Rig;

const std::size_t kElbow = joint_index_by_name("l_elbow");
const JointMask kElbowCut = joints_lost_by_link_failure_at(kElbow);  // l_elbow, l_wrist_yaw, l_wrist_pitch, l_hand
const JointMask kRightWristCut = joints_lost_by_link_failure_at(joint_index_by_name("r_wrist_yaw"));

// The EtherCAT handler's per-cycle duties that matter here.
struct FakeHandler {
  FakeHandler(Rig& rig, JointMask restored) : rig_(rig), tracker(rig.reports, rig.notices, restored) {}

  void cycle(hal::VirtualClock& clock) {
    ++number;
    clock.advance(hal::kNsPerMs);
    rig_.samples.lose(cut);  // the working counters miss them; their last values stay published
    tracker.on_cycle(number, clock.now(), cut);
    const JointMask commanded = kAllJoints & ~tracker.excluded();
    for (std::size_t j = 0; j < kJointCount; ++j) commanded_cycles[j] += (commanded & joint_bit(j)) != 0 ? 1 : 0;
    safe_stops += decide_safe_stop(rig_.samples.robot, commanded).stop ? 1 : 0;
  }

  Rig& rig_;
  LostJointTracker tracker;
  JointMask cut{0};
  std::uint64_t number{0};
  std::array<std::uint64_t, kJointCount> commanded_cycles{};
  int safe_stops{0};
};

class Reconfiguration : public ::testing::Test {
 protected:
  Reconfiguration() : storage(dir.path.c_str()), flaky(storage), rig(flaky), manager(rig.ports()), handler(rig, 0) {}

  // One period: the handler's cycle, then (unless busy) the joint manager's step.
  void run(int cycles, bool joint_manager_runs = true) {
    for (int i = 0; i < cycles; ++i) {
      handler.cycle(clock);
      if (joint_manager_runs) manager.step(clock.now());
    }
  }
  void initialize_robot() {
    rig.command(kAllJoints, JointInput::select_mode, ControlMode::cyclic_position);
    rig.command(kAllJoints, JointInput::set_reference);
    rig.command(kAllJoints, JointInput::enable);
    run(1);
  }
  ErrorJointsContents file_on_disk() {
    const ErrorJointsLoad load = storage.load();
    EXPECT_TRUE(load.file_present);
    EXPECT_TRUE(load.decoded.status.ok()) << load.decoded.status.error().what;
    return load.decoded.contents;
  }

  testing::TempStateDir dir;
  ErrorJointsFileStorage storage;
  testing::FlakyStorage flaky;
  Rig rig;
  JointManager manager;
  FakeHandler handler;
  hal::VirtualClock clock;
};

TEST_F(Reconfiguration, CutReportFileAnswerMarkAndTheHealthyJointsNeverMissACycle) {
  initialize_robot();
  run(999);  // one second of normal operation
  ASSERT_EQ(handler.number, 1000u);
  RobotSample before_cut = rig.samples.robot;

  handler.cut = kElbowCut;
  // The joint manager is busy for 200 ms (say, a slow disk): the handler must keep cycling anyway.
  run(200, /*joint_manager_runs=*/false);
  EXPECT_EQ(handler.tracker.pending(), kElbowCut);           // step 1 done, answer awaited
  EXPECT_EQ(handler.tracker.reports_sent(), 1u);
  EXPECT_EQ(rig.reports.size(), 1u);
  EXPECT_EQ(manager.statuses()[kElbow].state, JointState::enabled);  // not yet marked

  run(1);  // the joint manager handles the report in one step; the (inline) storage worker writes at once
  std::vector<int> steps;
  for (const JointEvent& e : rig.log.of(JointEventKind::reconfiguration_step)) steps.push_back(e.step);
  // Step 5 (Error) does not wait for the disk; steps 3-4 complete when the worker reports it durable.
  EXPECT_EQ(steps, (std::vector<int>{1, 2, 5, 3, 4}));
  run(1);  // step 6: the handler reads the answer and resumes with the others
  EXPECT_EQ(handler.tracker.pending(), 0u);
  EXPECT_EQ(handler.tracker.confirmed(), kElbowCut);
  EXPECT_EQ(handler.tracker.last_file_status(), Errc::ok);
  EXPECT_EQ(handler.tracker.last_answer_cycle(), 1003u);  // cut from cycle 1001: the third missed cycle

  // The file holds each lost joint, why, when, and where it is held.
  const ErrorJointsContents file = file_on_disk();
  ASSERT_EQ(file.records.size(), 4u);
  EXPECT_EQ(file.joints(), kElbowCut);
  for (const LostJointRecord& r : file.records) {
    EXPECT_EQ(r.reason, FaultReason::comm_lost);
    EXPECT_EQ(r.last_position_counts, drivers::rad_to_counts(before_cut[r.joint].position_rad)) << kJoints[r.joint].name;
    EXPECT_EQ(r.cycle, 1003u);
    EXPECT_EQ(r.time_unix_ns, rig.wall.unix_time_ns());
  }

  // The DFAs: lost joints in Error (comm_lost), held where they were; the rest still Enabled.
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const JointStatus& s = manager.statuses()[j];
    if (kElbowCut & joint_bit(j)) {
      EXPECT_EQ(s.state, JointState::error) << kJoints[j].name;
      EXPECT_TRUE(s.lost);
      EXPECT_FALSE(s.drive_enabled);
      EXPECT_EQ(s.fault.reason, FaultReason::comm_lost);
      EXPECT_EQ(s.held_position_rad, before_cut[j].position_rad);
    } else {
      EXPECT_EQ(s.state, JointState::enabled) << kJoints[j].name;
    }
  }
  EXPECT_EQ(manager.summary().condition, fsm::RobotCondition::degraded);

  run(500);
  EXPECT_EQ(handler.tracker.reports_sent(), 1u);  // reported once
  // No cycle of a healthy joint was missed, before, during or after the reconfiguration; the lost
  // joints stopped being commanded at the third missed cycle.
  for (std::size_t j = 0; j < kJointCount; ++j) {
    EXPECT_EQ(handler.commanded_cycles[j], (kElbowCut & joint_bit(j)) ? 1002u : handler.number) << kJoints[j].name;
  }
  EXPECT_EQ(handler.safe_stops, 0);
  EXPECT_EQ(manager.file_writes(), 1u);
}

TEST_F(Reconfiguration, RestartRestoresLostJointsBeforeTheNetworkAndTheHandlerExcludesThem) {
  initialize_robot();
  handler.cut = kElbowCut;
  run(10);
  const auto held = manager.statuses();

  // Power cycle: new joint manager, same state directory; the file is read before any cycle.
  Rig rig2(storage);
  JointManager restarted(rig2.ports());
  const RestoreReport report = restarted.restore(0);
  EXPECT_TRUE(report.file_present);
  EXPECT_TRUE(report.file_status.ok());
  EXPECT_EQ(report.restored, kElbowCut);
  EXPECT_TRUE(rig2.log.contains("error-joints file: restored l_elbow,l_wrist_yaw,l_wrist_pitch,l_hand in Error"));
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const JointStatus& s = restarted.statuses()[j];
    EXPECT_EQ(s.state, (kElbowCut & joint_bit(j)) ? JointState::error : JointState::idle) << kJoints[j].name;
    if (kElbowCut & joint_bit(j)) {
      EXPECT_TRUE(s.lost);
      EXPECT_EQ(s.held_position_rad, held[j].held_position_rad);  // RC tasks know where it is held
    }
  }
  FakeHandler handler2(rig2, report.restored);
  EXPECT_EQ(handler2.tracker.excluded(), kElbowCut);  // never commanded, from the first cycle
  handler2.cut = kElbowCut;
  hal::VirtualClock clock2;
  for (int i = 0; i < 20; ++i) {
    handler2.cycle(clock2);
    restarted.step(clock2.now());
  }
  EXPECT_EQ(handler2.tracker.reports_sent(), 0u);  // already known: nothing to report
}

TEST_F(Reconfiguration, OperatorClearsARepairedJointExplicitlyAndItComesBackThroughReset) {
  initialize_robot();
  handler.cut = kElbowCut;
  run(10);
  const std::size_t hand = joint_index_by_name("l_hand");

  EXPECT_FALSE(manager.clear_lost_joint(hand, clock.now()).ok());  // still unreachable
  EXPECT_TRUE(rig.log.contains("l_hand: operator clear refused: joint still unreachable: repair it first"));
  EXPECT_FALSE(manager.clear_lost_joint(joint_index_by_name("neck_pan"), clock.now()).ok());  // never lost
  EXPECT_FALSE(manager.clear_lost_joint(kJointCount, clock.now()).ok());

  // Repair: the link works again.
  handler.cut = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) rig.samples.robot[j].reachable = true;
  run(1);
  ASSERT_TRUE(manager.clear_lost_joint(hand, clock.now()).ok());  // accepted: done once durable
  EXPECT_TRUE(manager.clear_pending());
  EXPECT_FALSE(rig.log.contains("l_hand: cleared by operator after repair"));
  EXPECT_EQ(manager.lost_joints() & joint_bit(hand), joint_bit(hand));
  run(1);  // the write goes to the storage worker, which reports it durable
  EXPECT_FALSE(manager.clear_pending());
  EXPECT_TRUE(rig.log.contains("l_hand: cleared by operator after repair"));
  EXPECT_EQ(file_on_disk().joints(), kElbowCut & ~joint_bit(hand));  // durably out of the file
  EXPECT_EQ(manager.statuses()[hand].state, JointState::error);     // still Error until reset
  run(1);
  EXPECT_EQ(handler.tracker.confirmed(), kElbowCut & ~joint_bit(hand));  // the handler commands it again

  rig.command(joint_bit(hand), JointInput::reset);
  rig.command(joint_bit(joint_index_by_name("l_wrist_pitch")), JointInput::reset);  // not cleared: refused
  run(1);
  EXPECT_EQ(manager.statuses()[hand].state, JointState::idle);
  EXPECT_EQ(manager.statuses()[joint_index_by_name("l_wrist_pitch")].state, JointState::error);
}

TEST_F(Reconfiguration, AJointThatReturnsAwayFromItsHeldPositionStaysOutUntilTheOperatorConfirms) {
  initialize_robot();
  handler.cut = kElbowCut;
  run(10);
  const std::size_t hand = joint_index_by_name("l_hand");
  const std::size_t wrist = joint_index_by_name("l_wrist_pitch");

  // The link works again (the master recovered the drives); the hand was moved meanwhile.
  handler.cut = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) rig.samples.robot[j].reachable = true;
  rig.samples.robot[hand].position_rad += 0.5;
  run(2);
  EXPECT_TRUE(rig.log.contains("l_hand: answers again 0.5000 rad away from its held position"));
  EXPECT_TRUE(rig.log.contains("l_wrist_pitch: answers again at its held position"));

  EXPECT_FALSE(manager.clear_lost_joints(joint_bit(hand) | joint_bit(wrist), clock.now()).ok());
  EXPECT_TRUE(rig.log.contains("l_hand: operator clear refused: position differs from the held position"));
  run(1);  // the wrist's clear: durable
  EXPECT_EQ(file_on_disk().joints(), kElbowCut & ~joint_bit(wrist)) << "the wrist was cleared, the hand kept";
  EXPECT_EQ(manager.lost_joints() & joint_bit(hand), joint_bit(hand));

  // The operator confirms (`ctl clear l_hand --moved`: the parser's clear sequence with the
  // confirmation, clear_lost_moved then reset).
  const JointCommandSequence confirm = clear_repaired_joints_commands(joint_bit(hand), true);
  ASSERT_EQ(confirm[0].kind, JointCommandKind::clear_lost_moved);
  for (const JointCommand& c : confirm) ASSERT_TRUE(rig.commands.try_send(c));
  run(2);  // the clear, durable; then the reset behind it
  EXPECT_EQ(manager.lost_joints() & joint_bit(hand), 0u);
  EXPECT_EQ(manager.statuses()[hand].state, JointState::idle);
  EXPECT_EQ(file_on_disk().joints(), kElbowCut & ~joint_bit(hand) & ~joint_bit(wrist));
}

TEST_F(Reconfiguration, OperatorClearCommandClearsRepairedJointsInOneWriteAndRefusesTheRest) {
  initialize_robot();
  handler.cut = kElbowCut;
  run(10);
  const int saves_before = flaky.saves;

  // Repair: every joint answers again. The operator's "clear repaired" message names the cut joints
  // and one that was never lost.
  handler.cut = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) rig.samples.robot[j].reachable = true;
  run(1);
  const std::size_t neck = joint_index_by_name("neck_pan");
  for (const JointCommand& command : clear_repaired_joints_commands(kElbowCut | joint_bit(neck))) {
    ASSERT_TRUE(rig.commands.try_send(command));
  }
  run(2);
  EXPECT_EQ(flaky.saves, saves_before + 1);              // one durable write for the four joints
  EXPECT_EQ(file_on_disk().joints(), JointMask{0});
  EXPECT_EQ(manager.lost_joints(), JointMask{0});
  EXPECT_EQ(handler.tracker.confirmed(), JointMask{0});  // the handler commands them again
  EXPECT_TRUE(rig.log.contains("l_elbow: cleared by operator after repair"));
  EXPECT_TRUE(rig.log.contains("l_hand: cleared by operator after repair"));
  EXPECT_TRUE(rig.log.contains("neck_pan: operator clear refused: joint is not recorded as lost"));
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((kElbowCut & joint_bit(j)) != 0) {
      EXPECT_EQ(manager.statuses()[j].state, JointState::idle) << kJoints[j].name;
    }
  }
}

TEST_F(Reconfiguration, SecondCutKeepsTheFirstJointsInTheFile) {
  initialize_robot();
  handler.cut = kElbowCut;
  run(10);
  handler.cut = kElbowCut | kRightWristCut;
  run(10);
  EXPECT_EQ(file_on_disk().joints(), kElbowCut | kRightWristCut);
  EXPECT_EQ(file_on_disk().sequence, 2u);
  EXPECT_EQ(handler.tracker.confirmed(), kElbowCut | kRightWristCut);
  EXPECT_EQ(manager.lost_joints(), kElbowCut | kRightWristCut);
}

TEST_F(Reconfiguration, FailedWriteStillMarksTheJointsTellsTheHandlerAndRetries) {
  initialize_robot();
  flaky.fail_saves = true;
  handler.cut = kElbowCut;
  run(5);
  EXPECT_EQ(manager.statuses()[kElbow].state, JointState::error);  // safety does not wait for the disk
  EXPECT_EQ(handler.tracker.confirmed(), kElbowCut);
  EXPECT_EQ(handler.tracker.last_file_status(), Errc::io_error);
  EXPECT_TRUE(manager.file_dirty());
  EXPECT_TRUE(rig.log.contains("error-joints file NOT written: write temporary file (I/O error, errno 28); will retry"));
  EXPECT_FALSE(storage.load().file_present);
  // Issue 21: a failed write is never followed by a line saying it was written (step 3, "file
  // written"); the answer's line says the file does not hold them yet.
  EXPECT_TRUE(rig.log.of(JointEventKind::file_written).empty());
  EXPECT_FALSE(rig.log.contains("reconfiguration step 3 wrote the error-joints file"));
  EXPECT_TRUE(rig.log.contains("reconfiguration step 4 answered the handler: l_elbow,l_wrist_yaw,l_wrist_pitch,l_hand "
                               "(the error-joints file does NOT hold them yet: write temporary file; retrying)"));
  run(50);  // within the retry period: one attempt so far
  EXPECT_EQ(flaky.saves, 1);

  flaky.fail_saves = false;
  run(150);  // past the retry period
  EXPECT_FALSE(manager.file_dirty());
  EXPECT_EQ(file_on_disk().joints(), kElbowCut);
  EXPECT_EQ(manager.file_write_failures(), 1u);  // no retry storm: one attempt per retry period
  EXPECT_TRUE(rig.log.contains("reconfiguration step 3 wrote the error-joints file: l_elbow"));  // once durable
  EXPECT_EQ(handler.tracker.last_file_status(), Errc::ok);  // answered again, with the file's ok
}

TEST_F(Reconfiguration, ClearThatCannotBeWrittenIsRefusedAndNothingChanges) {
  initialize_robot();
  handler.cut = kElbowCut;
  run(10);
  handler.cut = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) rig.samples.robot[j].reachable = true;
  run(1);
  flaky.fail_saves = true;
  EXPECT_TRUE(manager.clear_lost_joint(kElbow, clock.now()).ok());  // accepted: it waits for the write
  EXPECT_FALSE(manager.clear_lost_joints(kElbowCut, clock.now()).ok());  // one clear at a time
  run(1);  // the write fails
  EXPECT_TRUE(rig.log.contains("l_elbow: operator clear refused: write temporary file"));
  EXPECT_FALSE(manager.clear_pending());
  EXPECT_FALSE(manager.file_dirty());  // the file on disk still holds every lost joint: nothing to retry
  EXPECT_EQ(manager.lost_joints(), kElbowCut);  // a clear that is not on disk did not happen
  EXPECT_EQ(file_on_disk().joints(), kElbowCut);

  // The operator's clear command for the set: refused for each joint.
  for (const JointCommand& c : clear_repaired_joints_commands(kElbowCut)) ASSERT_TRUE(rig.commands.try_send(c));
  run(110);  // the next write waits for the failed one's retry period (no retry storm)
  EXPECT_TRUE(rig.log.contains("l_wrist_yaw: operator clear refused: write temporary file"));
  EXPECT_EQ(manager.lost_joints(), kElbowCut);
  EXPECT_EQ(manager.statuses()[kElbow].state, JointState::error);  // the reset behind it: refused (loss latched)
  EXPECT_EQ(file_on_disk().joints(), kElbowCut);
}

TEST_F(Reconfiguration, FullNoticeQueueDefersTheAnswerWithoutLosingIt) {
  initialize_robot();
  rig.notices.set_capacity(0);
  handler.cut = kElbowCut;
  run(10);
  EXPECT_EQ(handler.tracker.pending(), kElbowCut);  // no answer yet: joints stay excluded (safe)
  EXPECT_TRUE(rig.log.contains("notice to the EtherCAT handler deferred"));
  rig.notices.set_capacity(4);
  run(2);
  EXPECT_EQ(handler.tracker.confirmed(), kElbowCut);
}

TEST_F(Reconfiguration, RepeatedReportIsAnsweredWithoutRewritingTheFile) {
  initialize_robot();
  handler.cut = kElbowCut;
  run(10);
  ASSERT_TRUE(rig.reports.try_send(LostJointsReport{kElbowCut, 77, 0}));
  run(2);
  EXPECT_EQ(manager.file_writes(), 1u);
  EXPECT_EQ(handler.tracker.last_answer_cycle(), 77u);
}

}  // namespace
}  // namespace rescue::app
