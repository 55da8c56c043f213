// The master's cyclic path stays heap-free while it recovers overlapping faults and watches every
// slave's AL state (issue 22): the heap guard armed in count mode after bring-up, then on the
// simulated robot in virtual time a drive with joints behind it switched off and on, a cut during
// that recovery, a SAFE-OP drop, and a hung drive whose recovery fails and is retried with its
// hold-off. Allocations counted: 0 (the simulator, a test object, allocates nothing per frame either).
#include <gtest/gtest.h>

#include <memory>

#include "core/memory/heap_guard.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

TEST(MasterHeapFree, RecoveriesAndTheAlStateWatchAllocateNothingAfterInit) {
  MasterOptions options = testing::fast_options();
  options.online_recovery = true;
  auto rig = testing::simulated_robot_in_op(options);
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  const auto position = [](const char* joint) { return slave_position_of_joint(joint_index_by_name(joint)); };
  LinkReport report;
  reopen_init_for_testing();
  declare_init_complete(HeapGuardMode::count);
  const auto run = [&](int periods) {
    for (int i = 0; i < periods; ++i) {
      (void)rig->cycle(refs, fb);
      while (rig->bus.master().pop_report(report)) {
      }
    }
  };
  (void)rig->segment.set_power(position("r_leg"), false, rig->clock.now());
  run(200);
  (void)rig->segment.set_power(position("r_leg"), true, rig->clock.now());
  run(10);
  (void)rig->segment.cut_link(position("waist_yaw"));
  (void)rig->segment.drop_to_safe_op(position("l_elbow"), reg::al_code::kSynchronizationError);
  (void)rig->segment.power_cycle(position("r_hand"), rig->clock.now());
  (void)rig->segment.freeze(position("r_hand"), true);
  run(300);
  (void)rig->segment.restore_link(position("waist_yaw"));
  run(4000);
  (void)rig->segment.freeze(position("r_hand"), false);
  run(6000);
  const HeapGuardCounters heap = heap_guard_counters();
  // The guard does count: one allocation of the test's own is seen.
  const std::unique_ptr<int> probe = std::make_unique<int>(1);
  const HeapGuardCounters after_probe = heap_guard_counters();
  reopen_init_for_testing();
  EXPECT_EQ(heap.allocations, 0U);
  EXPECT_EQ(after_probe.allocations, 1U) << *probe;
  EXPECT_GE(rig->bus.master().recovery_stats().recovered, 6U);
  EXPECT_GE(rig->bus.master().recovery_stats().failed, 1U);
  EXPECT_EQ(rig->bus.master().recovering(), 0U);
}

}  // namespace
}  // namespace rescue::ecat
