// No heap on the motion's real-time path: both RC tasks' periods (take of the motion, approach,
// the start of the rescue motion, its phases, a link cut mid-motion, an end-effector target, the
// teleop hands) and the EtherCAT handler's motion intake (owner's references, misses, the release
// of a dead owner), run with the heap guard in strict mode and Eigen's run-time malloc check: any
// allocation would abort the test.
#include <gtest/gtest.h>

#include "core/memory/heap_guard.hpp"
#include "tests/support/rc_task_rig.hpp"

namespace rescue::app {
namespace {

TEST(NoHeap, RcTaskPeriodsAndTheMotionIntakeNeverAllocate) {
  testing::RcTaskRig rig;  // init: everything allocated here
  rig.steps(2);

  reopen_init_for_testing();
  declare_init_complete(HeapGuardMode::strict);
  Eigen::internal::set_is_malloc_allowed(false);
  (void)rig.send(RcTaskId::rescue, RcInputKind::take_ownership);
  (void)rig.send(RcTaskId::teleop, RcInputKind::hand, 1, static_cast<std::uint8_t>(protocol::HandAction::close));
  rig.steps(1600 + 600);  // approach, the rescue motion's start, lowering, forwarding
  rig.cut_link_at(joint_index_by_name("l_elbow"));
  rig.steps(900);  // the rest of the motion on the remaining joints
  (void)rig.send(RcTaskId::rescue, RcInputKind::end_effector_target, 1, 0, {0.4, -0.3, 1.0, 0.0, 0.0, 0.0});
  rig.steps(200);
  rig.rescue_runs = false;  // the owner dies: misses, then its release
  rig.steps(100);
  (void)rig.send(RcTaskId::teleop, RcInputKind::take_ownership);
  rig.steps(50);
  Eigen::internal::set_is_malloc_allowed(true);
  const HeapGuardCounters counters = heap_guard_counters();
  reopen_init_for_testing();

  EXPECT_EQ(counters.allocations, 0U);
  EXPECT_EQ(counters.bytes, 0U);
  EXPECT_EQ(rig.intake.counters().releases, 1U) << "the path through a dead owner's release ran";
  EXPECT_EQ(rig.links->motion.owner.task(), 1);
  EXPECT_GT(rig.rescue->counters().owned_periods, 2000U);
}

}  // namespace
}  // namespace rescue::app
