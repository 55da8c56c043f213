// bench wcet's scenarios (docs/timing.md "Worst-path scenarios"): what makes each real-time task's
// period heaviest, and the load bench wcet puts on it to drive that path on purpose, on the simulated
// robot in virtual time. A scenario is a set of stresses; bench_wcet.cpp applies them.
//   typical   every joint Enabled, following its reference; the RC tasks doing the rescue motion
//   recovery  every slave power-cycled at once, again and again (at a seeded random gap): the master
//             loses all 23, recovers and re-integrates each (recovery, re-integration, PDO set-up,
//             OP step, start-up SDOs in the mailbox, link probes); the joint manager handles the loss
//             of every joint (its DFAs, the error-joints file) and clears them when they return; the
//             message parser re-initialises every joint; the RC tasks reshape after each change
//   services  the operator's segmented SDO transfers back to back in the mailbox, a diagnostics
//             reset every period, the capture on
//   worst     recovery and services at once, and more: every other loss a cut of the cable into the
//             first slave, repaired after a while (every slave re-armed or recovered behind it);
//             before each power cycle every drive's PDO mapping left as another drive's default (the
//             recovery reads, rewrites and reads it back); after every other power cycle the
//             re-initialise of every joint held until every joint is back, then sent at once (the
//             joint manager's heaviest period: a burst of the parser's commands while every joint
//             is monitored), after the others sent at random as in recovery; the message parser's
//             whole budget of requests in one period (an initialize of every joint while every
//             joint is initialised, each answered at once), early and after each loss; while
//             joints are down, a frame damaged on a random drive's cable in 1 of 40 periods (the
//             recovery's mailbox steps lose frames and are asked again); every service busy
//   worst-ring  worst on the robot's ring configuration (both master ports, docs/redundancy.md): every
//             period sends both copies and merges them, the ring monitor watches; every other loss
//             is a cut of the cable into the first slave (the DC reference), which opens the ring
//             with every slave behind the break: no joint lost, the ring DC service latches, reads
//             0x0918..0x092B of every DC slave behind the break and writes each its ring-side time
//             every period until the repair closes the ring; frames damaged (1 in 40 periods) while
//             joints are down, as in worst, and while every joint is Enabled: with the ring closed
//             the damaged exchange is sent again in its period (the in-flight repeat), with it open
//             the frame is lost while the DC service writes across the break
//   mixed     typical for the first half of the periods, recovery and services for the second (the
//             parser's requests at random periods while joints are down): not identically
//             distributed by construction, so the statistics must refuse it (CI checks the refusal)
#pragma once

#include <cstdint>

#include "core/base/span.hpp"

namespace rescue::app {

enum class WcetScenario : std::uint8_t { typical, recovery, services, worst, worst_ring, mixed };

struct WcetScenarioSpec {
  WcetScenario id;
  bool ring;  // on the robot's ring configuration (both master ports), else the tree
  const char* name;
  const char* what;  // one line for --help and the output
};

Span<const WcetScenarioSpec> wcet_scenarios() noexcept;
// The scenario called `name`; null when none is.
const WcetScenarioSpec* find_wcet_scenario(const char* name) noexcept;

// What a scenario does in measured period `k` of `periods`.
struct WcetStress {
  bool power_cycles{false};  // every slave power-cycled at a random gap
  bool services{false};      // SDO transfers, diagnostics reset every period, capture on
  bool cuts{false};          // every other loss a cut of the cable into the first slave, repaired
  bool pdo_rewrites{false};  // every drive's PDO mapping left wrong before each power cycle
  bool burst{false};         // after every other power cycle, the re-initialise of every joint held until every joint is back
  bool repeated_requests{false};  // the parser's budget of requests in one period, each answered at once (all joints unchanged)
  bool damaged_frames{false};     // while joints are down, a frame damaged on a random drive's cable in 1 of 40 periods
};
WcetStress wcet_stress(WcetScenario scenario, std::int64_t k, std::int64_t periods) noexcept;

}  // namespace rescue::app
