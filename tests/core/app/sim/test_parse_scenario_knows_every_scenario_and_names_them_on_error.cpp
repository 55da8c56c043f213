// parse_scenario (core/app/sim/run_scenario.cpp), the --scenario option of `run`: every known name
// gives its scenario (what it acts on, when, what the firmware must report lost, how long the run goes
// on), none/absent is no scenario, and an unknown name is an error naming the known ones.
#include <gtest/gtest.h>

#include <cstring>

#include "core/app/config/firmware_config.hpp"
#include "core/app/sim/run_scenario.hpp"

namespace rescue::app {
namespace {

TEST(ParseScenario, NoneOrAbsentIsNoScenario) {
  for (const char* name : {static_cast<const char*>(nullptr), "none"}) {
    const Result<Scenario> s = parse_scenario(name);
    ASSERT_TRUE(s.ok());
    EXPECT_EQ(s.value().kind, ScenarioKind::none);
    EXPECT_STREQ(s.value().name, "none");
    EXPECT_EQ(s.value().expected_lost, 0U);
    EXPECT_FALSE(s.value().rescue_motion);
  }
}

TEST(ParseScenario, EveryKnownScenarioActsOnTheLeftElbow) {
  const std::size_t elbow = joint_index_by_name("l_elbow");
  struct Expected {
    const char* name;
    ScenarioKind kind;
    hal::Nanoseconds cut_after_op;
    JointMask lost;
    hal::Nanoseconds run_on;
    bool rescue_motion;
  };
  const Expected expected[] = {
      {"link-cut", ScenarioKind::link_cut, hal::kNsPerSec, joints_lost_by_link_failure_at(elbow), config::kScenarioRunOnNs, false},
      {"power-cycle", ScenarioKind::power_cycle, hal::kNsPerSec, joint_bit(elbow), config::kScenarioRunOnNs, false},
      {"cable-damage", ScenarioKind::cable_damage, hal::kNsPerSec, 0, config::kScenarioRunOnNs, false},
      {"flaky-cable", ScenarioKind::cable_damage, hal::kNsPerSec, 0, config::kScenarioRunOnNs, false},
      {"rescue", ScenarioKind::rescue, 0, joints_lost_by_link_failure_at(elbow), 10 * hal::kNsPerSec, true},
  };
  for (const Expected& e : expected) {
    const Result<Scenario> s = parse_scenario(e.name);
    ASSERT_TRUE(s.ok()) << e.name;
    EXPECT_EQ(s.value().kind, e.kind) << e.name;
    EXPECT_STREQ(s.value().name, e.name);
    EXPECT_EQ(s.value().cut_joint, elbow) << e.name;
    EXPECT_EQ(s.value().cut_after_op, e.cut_after_op) << e.name;
    EXPECT_EQ(s.value().expected_lost, e.lost) << e.name;
    EXPECT_EQ(s.value().run_on, e.run_on) << e.name;
    EXPECT_EQ(s.value().rescue_motion, e.rescue_motion) << e.name;
    EXPECT_EQ(s.value().repeat_every, std::strcmp(e.name, "flaky-cable") == 0 ? 2 * hal::kNsPerSec : 0) << e.name;
    const std::array<double, 3> phases = e.rescue_motion ? std::array<double, 3>{1.0, 1.0, 1.0} : std::array<double, 3>{};
    EXPECT_EQ(s.value().motion_phase_s, phases) << e.name;
    // The rescue cut waits for the forwarding phase, wherever a loaded host puts it in wall time.
    EXPECT_EQ(s.value().cut_into_forwarding, e.rescue_motion ? 300 * hal::kNsPerMs : -1) << e.name;
  }
  EXPECT_NE(joints_lost_by_link_failure_at(elbow), joint_bit(elbow));  // the branch, not only the joint
}

TEST(ParseScenario, AnUnknownNameIsAnErrorNamingTheKnownOnes) {
  const Result<Scenario> s = parse_scenario("earthquake");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, Errc::invalid_argument);
  for (const char* known : {"none", "link-cut", "rescue", "power-cycle", "cable-damage", "flaky-cable"}) {
    EXPECT_NE(std::strstr(s.error().what, known), nullptr) << known;
  }
}

}  // namespace
}  // namespace rescue::app
