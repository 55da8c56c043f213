#include <gtest/gtest.h>
#include <cstdio>
#include "tests/support/simulated_robot_rig.hpp"
namespace rescue::ecat {
namespace {
void run_case(hal::Nanoseconds gap, int stall_at, bool cut) {
  ecat::MasterOptions o = testing::fast_options();
  o.online_recovery = true;
  auto rig = testing::simulated_robot_in_op(o);
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  for (int i = 0; i < 50; ++i) (void)rig->cycle(refs, fb);
  LinkReport r;
  while (rig->bus.master().pop_report(r)) {}
  if (stall_at < 0) rig->clock.advance(gap);
  if (cut) { ASSERT_TRUE(rig->segment.cut_link(slave_position_of_joint(joint_index_by_name("l_elbow"))).ok()); }
  std::string out;
  int invalid = 0;
  for (int i = 0; i < 300; ++i) {
    if (i == stall_at) rig->clock.advance(gap);
    auto c = rig->cycle(refs, fb);
    if (i > 3 && (c.valid | joints_lost_by_link_failure_at(joint_index_by_name("l_elbow"))) != kAllJoints) ++invalid;
    while (rig->bus.master().pop_report(r)) {
      char line[200];
      std::snprintf(line, sizeof line, " [c+%d %s slaves 0x%llx al 0x%x code 0x%x]", i, to_string(r.kind),
                    static_cast<unsigned long long>(r.slaves), r.al_status, r.al_status_code);
      out += line;
    }
  }
  std::string states;
  for (std::size_t p = 0; p < kSlaveCount; ++p) states += std::to_string(static_cast<int>(rig->segment.esc(p).al_state()));
  std::printf("gap %lld ms at %d cut %d: invalid %d states %s:%s\n", static_cast<long long>(gap / hal::kNsPerMs), stall_at, cut, invalid, states.c_str(), out.c_str());
}
TEST(Explore, StallAroundCut) {
  for (hal::Nanoseconds g : {20, 60, 101, 150, 500}) {
    for (int at : {-1, 0, 1, 2, 3, 10}) run_case(g * hal::kNsPerMs, at, true);
  }
  run_case(150 * hal::kNsPerMs, 10, false);
}
}  // namespace
}  // namespace rescue::ecat
