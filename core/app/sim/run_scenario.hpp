// Scenarios of `rescue-motion run` on the simulated robot: scripted faults injected into the
// simulated segment at set times, so the firmware's reaction can be watched end to end.
//
//   link-cut  one second after the network reached OP, the cable into l_elbow is cut: l_elbow,
//             l_wrist_yaw, l_wrist_pitch and l_hand become unreachable (design brief section 6)
//   power-cycle  one second after OP, l_elbow's drive is power-cycled (its ESC loses its registers and
//             station address): l_elbow is lost, and the master's online recovery brings it back
//   cable-damage  one second after OP, 5 frames are damaged on the cable into l_elbow's port 0: the
//             link diagnostics count them and warn, naming the cable; no joint is lost
//
// The scenario acts from the EtherCAT handler's thread, between two cycles (the simulated segment
// is driven by that thread's frames), and only on the simulated NIC.
#pragma once

#include <cstdint>

#include "core/base/result.hpp"
#include "core/robot/robot.hpp"
#include "drivers/sim/segment/simulated_segment.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

enum class ScenarioKind : std::uint8_t { none, link_cut, power_cycle, cable_damage };

struct Scenario {
  ScenarioKind kind{ScenarioKind::none};
  const char* name{"none"};
  std::size_t cut_joint{kJointCount};   // link_cut: the joint whose incoming cable is cut; power_cycle: the joint
  hal::Nanoseconds cut_after_op{0};     // link_cut: how long after OP
  JointMask expected_lost{0};           // link_cut: what the firmware must report
};

// Parses --scenario (nullptr: none). Unknown names are an error naming the known ones.
Result<Scenario> parse_scenario(const char* name) noexcept;

// Drives a scenario: call after every cycle with the cycle's time and whether the master is in OP.
class ScenarioRunner {
 public:
  ScenarioRunner(const Scenario& scenario, drivers::SimulatedSegment* segment) noexcept
      : scenario_(scenario), segment_(segment) {}

  // Returns true in the cycle the scenario acted (the caller logs it).
  bool on_cycle(hal::Nanoseconds now, bool network_op) noexcept;

  bool acted() const noexcept { return acted_; }
  hal::Nanoseconds acted_at() const noexcept { return acted_at_; }
  const Scenario& scenario() const noexcept { return scenario_; }
  const Status& action_status() const noexcept { return action_status_; }

 private:
  Scenario scenario_;
  drivers::SimulatedSegment* segment_;
  hal::Nanoseconds op_at_{-1};
  bool acted_{false};
  hal::Nanoseconds acted_at_{0};
  Status action_status_{};
};

}  // namespace rescue::app
