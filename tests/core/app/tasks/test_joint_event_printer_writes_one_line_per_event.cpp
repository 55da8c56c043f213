#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/app/tasks/joint_event_printer.hpp"

namespace rescue::app {
namespace {

TEST(JointEventPrinter, WritesPrefixTimeAndTheEventsLine) {
  char* buf = nullptr;
  std::size_t len = 0;
  FILE* out = open_memstream(&buf, &len);
  ASSERT_NE(out, nullptr);
  JointEventPrinter printer(out, "joint-manager: ");
  printer.set_origin(1'000 * hal::kNsPerMs);  // times print relative to the program's start
  JointEvent e;
  e.kind = JointEventKind::transition;
  e.time = 2'234 * hal::kNsPerMs;
  e.joint = static_cast<std::uint8_t>(joint_index_by_name("l_elbow"));
  e.from = fsm::JointState::enabled;
  e.to = fsm::JointState::error;
  e.input = fsm::JointInput::comm_lost;
  printer.print(e);
  e.kind = JointEventKind::reconfiguration_step;
  e.step = 3;
  e.joints = joints_lost_by_link_failure_at(e.joint);
  printer.print(e);
  std::fclose(out);
  const std::string text(buf, len);
  std::free(buf);
  EXPECT_EQ(text,
            "[   1.234 s] joint-manager: l_elbow: Enabled --comm_lost--> Error\n"
            "[   1.234 s] joint-manager: reconfiguration step 3 wrote the error-joints file: "
            "l_elbow,l_wrist_yaw,l_wrist_pitch,l_hand\n");
}

}  // namespace
}  // namespace rescue::app
