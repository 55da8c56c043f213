// `run --scenario rescue` (core/app/sim/run_scenario.*): the cable into l_elbow is cut 0.3 s into
// the rescue motion's forwarding phase, whenever the rescue task reaches it. A loaded host stretches
// the motion in wall time (a debug build's RC task under stress-ng missed 3212 of 9300 periods):
// the former cut at a fixed 3 s after OP then fell in the lowering and the scenario's story broke.
#include <gtest/gtest.h>

#include "core/app/sim/run_scenario.hpp"

namespace rescue::app {
namespace {

constexpr hal::Nanoseconds kMs = hal::kNsPerMs;

TEST(RescueScenario, TheCutWaitsForTheForwardingPhaseHoweverLateItComes) {
  const Result<Scenario> parsed = parse_scenario("rescue");
  ASSERT_TRUE(parsed.ok());
  ScenarioRunner runner(parsed.value(), nullptr);
  hal::Nanoseconds now = 1000 * kMs;
  // In OP, 20 s of approach and lowering (a very slow host): no cut.
  for (int k = 0; k < 20'000; ++k, now += kMs) EXPECT_FALSE(runner.on_cycle(now, true, false)) << k;
  EXPECT_FALSE(runner.acted());
  // Forwarding from now on: the cut comes 300 ms later, once.
  const hal::Nanoseconds forwarding_at = now;
  int acted = 0;
  for (int k = 0; k < 1000; ++k, now += kMs) {
    if (runner.on_cycle(now, true, true)) {
      ++acted;
      EXPECT_EQ(now - forwarding_at, 300 * kMs);
    }
  }
  EXPECT_EQ(acted, 1);
  EXPECT_TRUE(runner.acted());
  EXPECT_FALSE(runner.action_status().ok()) << "no simulated robot here: the action says so";
}

TEST(RescueScenario, OtherScenariosStillActAtTheirTimeAfterOp) {
  const Result<Scenario> parsed = parse_scenario("link-cut");
  ASSERT_TRUE(parsed.ok());
  ScenarioRunner runner(parsed.value(), nullptr);
  hal::Nanoseconds now = 1000 * kMs;
  const hal::Nanoseconds op_at = now;
  while (!runner.on_cycle(now, true, false)) now += kMs;
  EXPECT_EQ(now - op_at, hal::kNsPerSec);
}

}  // namespace
}  // namespace rescue::app
