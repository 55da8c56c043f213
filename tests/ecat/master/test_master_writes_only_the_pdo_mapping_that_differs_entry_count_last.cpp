// The master sets up each drive's PDO assignment and mapping from the plan (ecat/master/pdo_setup.hpp,
// docs/master.md "PDO mapping"), in virtual time on the simulated robot: it reads what the drive
// holds and writes only what differs, in ETG.1020's order (assignment count 0, mapping count 0,
// the differing entries, the mapping count last, the assignment count last), then reads it back.
// A drive left half-mapped or with another drive's default mapping reaches OP at bring-up and after a
// power cycle in online recovery; a healthy drive costs reads only (four whole objects when its SII
// announces SDO complete access, else one subindex at a time, and one at a time what a complete
// access does not give); many drives recovering at once never overflow the 32-deep mailbox queue.
#include <gtest/gtest.h>

#include <array>

#include <string>

#include <vector>

#include "drivers/joint/robot_network_plan.hpp"
#include "ecat/master/bring_up_report.hpp"
#include "ecat/master/pdo_setup.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using drivers::kJointDrivePdoPlan;
using drivers::PdoMappingFault;
using testing::SimulatedRobotRig;

struct Write {
  std::uint16_t index;
  std::uint8_t subindex;
  std::uint32_t value;
  bool operator==(const Write& o) const { return index == o.index && subindex == o.subindex && value == o.value; }
};

std::vector<Write> writes_for(const PdoMappingPlan& plan, const PdoMappingState& current) {
  std::array<SdoRequest, kPdoWritesPerDirection> out{};
  const std::size_t n = pdo_mapping_writes(3, plan, current, out.data(), out.size());
  std::vector<Write> w;
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(out[i].direction, SdoDirection::download);
    EXPECT_EQ(out[i].position, 3);
    w.push_back(Write{out[i].index, out[i].subindex, sdo_value(SdoCompletion{out[i], SdoOutcome::ok, 0, 0, out[i].size, out[i].data, 0})});
  }
  return w;
}

PdoMappingState as_planned(const PdoMappingPlan& plan) {
  PdoMappingState s;
  s.assign_count = 1;
  s.assigned = plan.pdo_index;
  s.entry_count = plan.entry_count;
  for (std::size_t i = 0; i < plan.entry_count; ++i) s.entries[i] = plan.entries[i];
  return s;
}

TEST(PdoMappingWrites, NoneWhenTheDriveHoldsThePlan) {
  EXPECT_TRUE(writes_for(kJointDrivePdoPlan.outputs, as_planned(kJointDrivePdoPlan.outputs)).empty());
  EXPECT_TRUE(writes_for(kJointDrivePdoPlan.inputs, as_planned(kJointDrivePdoPlan.inputs)).empty());
}

TEST(PdoMappingWrites, AHalfWrittenMappingGetsItsEntryCountOnlyBetweenAssignmentCounts) {
  PdoMappingState s = as_planned(kJointDrivePdoPlan.outputs);
  s.entry_count = 0;
  const std::vector<Write> expected{{0x1C12, 0, 0}, {0x1600, 0, 5}, {0x1C12, 0, 1}};
  EXPECT_EQ(writes_for(kJointDrivePdoPlan.outputs, s), expected);
}

TEST(PdoMappingWrites, AForeignMappingGetsTheDifferingEntriesThenTheCountThenTheAssignment) {
  PdoMappingState s = as_planned(kJointDrivePdoPlan.inputs);
  s.entry_count = 2;
  s.entries = {0x60410010U, 0x60640020U, 0, 0, 0, 0, 0, 0};
  s.assigned = 0x1A01;
  const std::vector<Write> expected{{0x1C13, 0, 0},          {0x1A00, 0, 0},          {0x1A00, 2, 0x60610008U},
                                    {0x1A00, 3, 0x60640020U}, {0x1A00, 4, 0x606C0020U}, {0x1A00, 5, 0x60770010U},
                                    {0x1A00, 6, 0x603F0010U}, {0x1A00, 0, 6},          {0x1C13, 1, 0x1A00},
                                    {0x1C13, 0, 1}};
  EXPECT_EQ(writes_for(kJointDrivePdoPlan.inputs, s), expected);
}

TEST(PdoMappingWrites, AnEntryThatCouldNotBeReadIsWritten) {
  PdoMappingState s = as_planned(kJointDrivePdoPlan.outputs);
  s.unknown = 1U << 4;  // entry 2
  const std::vector<Write> expected{{0x1C12, 0, 0}, {0x1600, 0, 0}, {0x1600, 2, kJointDrivePdoPlan.outputs.entries[1]},
                                    {0x1600, 0, 5}, {0x1C12, 0, 1}};
  EXPECT_EQ(writes_for(kJointDrivePdoPlan.outputs, s), expected);
}

// A drive answering PdoSetup's uploads from what it holds (`held`: outputs, inputs), aborting every
// complete access when `refuse_complete_access`. Runs the set-up's reads to their end (done, or the
// writes next); the uploads it was asked.
struct Asked {
  std::size_t whole{0};
  std::size_t single{0};
};
Asked answer_reads(PdoSetup& setup, const std::array<PdoMappingState, 2>& held, bool refuse_complete_access) {
  Asked asked;
  SdoRequest r;
  for (int guard = 0; guard < 100 && setup.phase() == PdoSetup::Phase::reading && setup.next(r); ++guard) {
    EXPECT_EQ(r.direction, SdoDirection::upload);
    SdoCompletion done{};
    done.request = r;
    const bool outputs = r.index == 0x1C12 || r.index == 0x1600;
    const PdoMappingState& h = held[outputs ? 0 : 1];
    const bool assignment = r.index == 0x1C12 || r.index == 0x1C13;
    if (r.complete_access) {
      ++asked.whole;
      EXPECT_EQ(r.subindex, 0);
      if (refuse_complete_access) {
        done.outcome = SdoOutcome::aborted;
        done.abort_code = 0x06010000U;
      } else {
        const std::uint32_t count = assignment ? h.assign_count : h.entry_count;
        done.data[0] = static_cast<std::uint8_t>(count);
        std::size_t at = 2;
        for (std::uint32_t i = 0; i < count; ++i) {
          if (assignment) {
            store_le16(done.data.data() + at, static_cast<std::uint16_t>(h.assigned));
            at += 2;
          } else {
            store_le32(done.data.data() + at, h.entries[i]);
            at += 4;
          }
        }
        done.size = static_cast<std::uint16_t>(at);
      }
    } else {
      ++asked.single;
      std::uint32_t value = 0;
      if (assignment) {
        value = r.subindex == 0 ? h.assign_count : h.assigned;
      } else {
        value = r.subindex == 0 ? h.entry_count : h.entries[r.subindex - 1U];
      }
      store_le32(done.data.data(), value);
      done.size = r.subindex == 0 ? 1 : (assignment ? 2 : 4);
    }
    setup.on_completion(done);
  }
  return asked;
}

// A drive holding the plan, read with or without complete access: the uploads asked, nothing written.
Asked reads_of_a_healthy_drive(bool complete_access, bool refuse_complete_access) {
  PdoSetup setup;
  setup.start(3, &kJointDrivePdoPlan, complete_access);
  const Asked asked =
      answer_reads(setup, {as_planned(kJointDrivePdoPlan.outputs), as_planned(kJointDrivePdoPlan.inputs)}, refuse_complete_access);
  EXPECT_EQ(setup.phase(), PdoSetup::Phase::done);
  EXPECT_EQ(setup.writes(), 0u);
  return asked;
}

TEST(PdoSetupReads, FourWholeObjectsWhenTheSlaveOffersCompleteAccess) {
  const Asked asked = reads_of_a_healthy_drive(true, false);
  EXPECT_EQ(asked.whole, 4u);
  EXPECT_EQ(asked.single, 0u);
}

TEST(PdoSetupReads, OneSubindexAtATimeWithoutCompleteAccess) {
  const Asked asked = reads_of_a_healthy_drive(false, false);
  EXPECT_EQ(asked.whole, 0u);
  EXPECT_EQ(asked.single, 17u);
}

TEST(PdoSetupReads, AnAbortedCompleteAccessIsReadOneSubindexAtATime) {
  const Asked asked = reads_of_a_healthy_drive(true, true);
  EXPECT_EQ(asked.whole, 4u);
  EXPECT_EQ(asked.single, 17u);
}

TEST(PdoSetupReads, AHalfWrittenMappingSeenWholeGetsTheSameThreeWrites) {
  // Its entry count 0: the complete access gives no entries, so they are read singly, and the
  // writes are those of the single reads (the entries as planned are not written again).
  PdoMappingState half = as_planned(kJointDrivePdoPlan.outputs);
  half.entry_count = 0;
  PdoSetup setup;
  setup.start(3, &kJointDrivePdoPlan, true);
  SdoRequest r;
  std::array<PdoMappingState, 2> held{half, as_planned(kJointDrivePdoPlan.inputs)};
  const Asked asked = answer_reads(setup, held, false);
  EXPECT_EQ(setup.phase(), PdoSetup::Phase::writing);
  EXPECT_EQ(asked.whole, 4u);
  EXPECT_EQ(asked.single, 5u);
  std::vector<Write> writes;
  while (setup.phase() == PdoSetup::Phase::writing && setup.next(r)) {
    writes.push_back(Write{r.index, r.subindex, load_le32(r.data.data()) & (r.size == 1 ? 0xFFU : 0xFFFFFFFFU)});
    SdoCompletion done{};
    done.request = r;
    setup.on_completion(done);
  }
  const std::vector<Write> expected{{0x1C12, 0, 0}, {0x1600, 0, 5}, {0x1C12, 0, 1}};
  EXPECT_EQ(writes, expected);
}

// The mapping the drive of `joint` holds now, as the plan's state.
bool drive_holds_the_plan(SimulatedRobotRig& rig, std::size_t joint) {
  const drivers::ObjectDictionary& od = rig.drive(joint).objects().od();
  for (const PdoMappingPlan* m : {&kJointDrivePdoPlan.outputs, &kJointDrivePdoPlan.inputs}) {
    if (od.get_u32(m->assign_index, 0) != 1 || od.get_u32(m->assign_index, 1) != m->pdo_index) return false;
    if (od.get_u32(m->pdo_index, 0) != m->entry_count) return false;
    for (std::size_t i = 0; i < m->entry_count; ++i) {
      if (od.get_u32(m->pdo_index, static_cast<std::uint8_t>(i + 1)) != m->entries[i]) return false;
    }
  }
  return true;
}

void cycle_to_op(SimulatedRobotRig& rig) {
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  for (int i = 0; i < 300 && rig.bus.master().state() != MasterState::op; ++i) (void)rig.cycle(refs, fb);
}

// The drives' SII announces SDO complete access: 0x1C12, 0x1600, 0x1C13 and 0x1A00 whole.
constexpr std::size_t kReadsPerDrive = 4;

TEST(MasterPdoMappingAtBringUp, AHealthyRobotCostsReadsOnly) {
  auto rig = testing::simulated_robot_in_op();
  const BringUpReport& r = rig->bus.master().report();
  EXPECT_EQ(r.pdo_writes, 0u);
  EXPECT_EQ(r.pdo_rewritten, 0u);
  EXPECT_EQ(r.pdo_reads, kJointCount * kReadsPerDrive);
}

// Frames of bring-up step `name` (from its mark to the next one's).
std::uint64_t frames_of_step(const BringUpReport& r, const char* name) {
  for (std::size_t k = 0; k + 1 < r.step_count; ++k) {
    if (std::string(r.steps[k].step) == name) return r.steps[k + 1].frames - r.steps[k].frames;
  }
  return 0;
}

// Each drive's mailbox holds one message, but the drives are independent: their transfers run side
// by side, so the step takes far fewer frames than it has transfers (one at a time on the segment
// took two frames a transfer).
TEST(MasterPdoMappingAtBringUp, TheDrivesAreReadSideBySideInFewerFramesThanTransfers) {
  auto rig = testing::simulated_robot_in_op();
  const BringUpReport& r = rig->bus.master().report();
  const std::uint64_t transfers = r.pdo_reads + r.startup_sdos_done;
  const std::uint64_t frames = frames_of_step(r, "PRE-OP SDO");
  EXPECT_GT(frames, 0u);
  EXPECT_LT(3 * frames, transfers) << frames << " frames for " << transfers << " transfers";
}

TEST(MasterPdoMappingAtBringUp, AHalfWrittenMappingIsCompletedWithThreeWritesAndReachesOp) {
  SimulatedRobotRig rig;
  const std::size_t joint = joint_index_by_name("r_shoulder_pitch");
  ASSERT_TRUE(rig.segment.corrupt_pdo_mapping(slave_position_of_joint(joint), PdoMappingFault::half_written).ok());
  ASSERT_FALSE(rig.drive(joint).objects().mapping_is_complete());
  ASSERT_TRUE(rig.bus.bring_up(testing::fast_options()).ok()) << testing::describe_master_failure(rig.bus.master());
  const BringUpReport& r = rig.bus.master().report();
  EXPECT_EQ(r.pdo_rewritten, slave_bit(slave_position_of_joint(joint)));
  EXPECT_EQ(r.pdo_writes, 3u);  // 0x1C12:00 = 0, 0x1600:00 = 5, 0x1C12:00 = 1
  // Its 5 output entries singly (the complete access of 0x1600 gave its count 0 only), its read-back.
  EXPECT_EQ(r.pdo_reads, kJointCount * kReadsPerDrive + 5 + kReadsPerDrive);
  EXPECT_TRUE(drive_holds_the_plan(rig, joint));
  cycle_to_op(rig);
  EXPECT_EQ(rig.bus.master().state(), MasterState::op);
}

TEST(MasterPdoMappingAtBringUp, AForeignDefaultMappingIsRewrittenAndReachesOp) {
  SimulatedRobotRig rig;
  const std::size_t joint = joint_index_by_name("l_leg");
  ASSERT_TRUE(rig.segment.corrupt_pdo_mapping(slave_position_of_joint(joint), PdoMappingFault::foreign_default).ok());
  ASSERT_TRUE(rig.bus.bring_up(testing::fast_options()).ok()) << testing::describe_master_failure(rig.bus.master());
  const BringUpReport& r = rig.bus.master().report();
  EXPECT_EQ(r.pdo_rewritten, slave_bit(slave_position_of_joint(joint)));
  // Outputs: 2 counts cleared, entries 2..5, count, assignment count (8); inputs: the same with entries 2..6 (9).
  EXPECT_EQ(r.pdo_writes, 17u);
  EXPECT_TRUE(drive_holds_the_plan(rig, joint));
  cycle_to_op(rig);
  EXPECT_EQ(rig.bus.master().state(), MasterState::op);
}

TEST(MasterPdoMappingAtBringUp, AMappingTheDriveRefusesFailsTheBringUpNamingTheDriveAndTheAbortCode) {
  SimulatedRobotRig rig;
  // A plan asking r_elbow for digital outputs (0x60FE:01, 32 bits) in place of the target velocity:
  // the same image size, a mapping the drive refuses.
  const std::size_t p = slave_position_of_joint(joint_index_by_name("r_elbow"));
  static constexpr std::array<std::uint32_t, 5> kWrongRx{0x60400010U, 0x60600008U, 0x607A0020U, 0x60FE0120U, 0x60710010U};
  static constexpr SlavePdoPlan kWrongPlan{{0x1C12, 0x1600, kWrongRx.data(), 5}, kJointDrivePdoPlan.inputs};
  static NetworkPlan plan = drivers::kRobotNetworkPlan;
  plan[p].pdo = &kWrongPlan;
  std::array<std::uint8_t, drivers::kRobotImageBytes> image{};
  auto master = std::make_unique<Master>(rig.nic, plan, drivers::kRobotImageLayout, ByteSpan(image));
  ASSERT_FALSE(master->bring_up(testing::fast_options()).ok());
  const BringUpReport& r = master->report();
  ASSERT_NE(r.failed_step, nullptr);
  EXPECT_STREQ(r.failed_step, "PRE-OP SDO");
  EXPECT_EQ(r.failed_sdo.request.position, p);
  EXPECT_EQ(r.failed_sdo.request.index, 0x1600);
  EXPECT_EQ(r.failed_sdo.request.subindex, 4);
  EXPECT_EQ(r.failed_sdo.outcome, SdoOutcome::aborted);
  EXPECT_EQ(r.failed_sdo.abort_code, 0x06040041u);
  char text[2048] = {};
  std::FILE* out = fmemopen(text, sizeof text - 1, "w");
  ASSERT_NE(out, nullptr);
  print_bring_up_failure(out, "", "  ", *master);
  (void)std::fclose(out);
  const std::string report(text);
  EXPECT_NE(report.find("bring-up failed at PRE-OP SDO: PDO mapping not set (refused: slave at position 5, object 0x1600:04)\n"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("start-up SDO download 0x1600:04 to r_elbow: aborted, abort code 0x06040041 object cannot be mapped to the PDO"),
            std::string::npos)
      << report;
}

MasterOptions recovery_options() {
  MasterOptions options = testing::fast_options();
  options.online_recovery = true;
  return options;
}

// Cycles until every slave of `slaves` is back in the exchange (recovered) or `limit` periods passed;
// `reported_writes` (when given) gets the PDO mapping writes each `recovered` report names (found[1],
// what the run's log line prints as bring-up does).
SlaveMask cycle_until_recovered(SimulatedRobotRig& rig, SlaveMask slaves, int limit,
                                std::array<std::uint32_t, kMaxSlaves>* reported_writes = nullptr) {
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  SlaveMask recovered = 0;
  LinkReport report;
  for (int i = 0; i < limit && recovered != slaves; ++i) {
    (void)rig.cycle(refs, fb);
    // Each recovering slave holds one place in the queue at most: the owner's room stays.
    EXPECT_GE(rig.bus.master().mailbox().free_slots(), MailboxClient::kQueueCapacity - kMaxSlaves);
    while (rig.bus.master().pop_report(report)) {
      if (report.kind != LinkEventKind::recovered) continue;
      recovered |= report.slaves;
      for (std::size_t p = 0; p < kMaxSlaves && reported_writes != nullptr; ++p) {
        if ((report.slaves & slave_bit(p)) != 0) (*reported_writes)[p] = report.found[1];
      }
    }
  }
  return recovered;
}

TEST(MasterPdoMappingInRecovery, APowerCycledDriveWithAHalfWrittenMappingIsRepairedAndReturns) {
  auto rig = testing::simulated_robot_in_op(recovery_options());
  const std::size_t joint = joint_index_by_name("l_elbow");
  const std::size_t p = slave_position_of_joint(joint);
  ASSERT_TRUE(rig->segment.corrupt_pdo_mapping(p, PdoMappingFault::half_written).ok());
  ASSERT_TRUE(rig->segment.power_cycle(p, rig->clock.now()).ok());
  std::array<std::uint32_t, kMaxSlaves> reported{};
  EXPECT_EQ(cycle_until_recovered(*rig, slave_bit(p), 2000, &reported), slave_bit(p));
  EXPECT_EQ(rig->bus.master().recovery_pdo_writes(p), 3u);
  EXPECT_EQ(reported[p], 3u) << "the recovered report says the mapping was rewritten (issue 35 item 15)";
  EXPECT_TRUE(drive_holds_the_plan(*rig, joint));
  EXPECT_EQ(rig->segment.esc(p).al_state(), reg::AlState::op);
  // A drive that comes back holding the plan: nothing written, nothing said.
  const std::size_t other = slave_position_of_joint(joint_index_by_name("r_elbow"));
  ASSERT_TRUE(rig->segment.power_cycle(other, rig->clock.now()).ok());
  reported[other] = 99;
  EXPECT_EQ(cycle_until_recovered(*rig, slave_bit(other), 2000, &reported), slave_bit(other));
  EXPECT_EQ(reported[other], 0u);
}

TEST(MasterPdoMappingInRecovery, EveryDriveWithAForeignMappingPowerCycledAtOnceReturnsWithoutOverflowingTheQueue) {
  auto rig = testing::simulated_robot_in_op(recovery_options());
  SlaveMask drives = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const std::size_t p = slave_position_of_joint(j);
    drives |= slave_bit(p);
    ASSERT_TRUE(rig->segment.corrupt_pdo_mapping(p, PdoMappingFault::foreign_default).ok());
  }
  for (std::size_t j = 0; j < kJointCount; ++j) {
    ASSERT_TRUE(rig->segment.power_cycle(slave_position_of_joint(j), rig->clock.now()).ok());
  }
  // 21 drives x (17 reads + 17 writes + 17 read back + 5 limits): far more than the queue's 32.
  std::array<std::uint32_t, kMaxSlaves> reported{};
  EXPECT_EQ(cycle_until_recovered(*rig, drives, 30000, &reported), drives);
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const std::size_t p = slave_position_of_joint(j);
    EXPECT_EQ(rig->bus.master().recovery_pdo_writes(p), 17u) << kJoints[j].name;
    EXPECT_EQ(reported[p], 17u) << kJoints[j].name;
    EXPECT_TRUE(drive_holds_the_plan(*rig, j)) << kJoints[j].name;
    EXPECT_EQ(rig->segment.esc(p).al_state(), reg::AlState::op) << kJoints[j].name;
  }
  EXPECT_EQ(rig->bus.master().recovery_stats().failed, 0u);
}

}  // namespace
}  // namespace rescue::ecat
