// Scenarios of `rescue-motion run` on the simulated robot: scripted faults injected into the
// simulated segment at set times, so the firmware's reaction can be watched end to end.
//
//   link-cut  one second after the network reached OP, the cable into l_elbow is cut: l_elbow,
//             l_wrist_yaw, l_wrist_pitch and l_hand become unreachable (design brief section 6)
//   power-cycle  one second after OP, l_elbow's drive is power-cycled (its ESC loses its registers and
//             station address): l_elbow is lost, and the master's online recovery brings it back
//   half-mapped  l_elbow's drive comes with its RxPDO mapping half-written (0x1600 entries written,
//             0x1600:00 left at 0, as a tool that stopped halfway leaves it): the master rewrites it at
//             bring-up; one second after OP the mapping is left half-written again and the drive
//             power-cycled: the online recovery rewrites it and brings l_elbow back (as power-cycle)
//   foreign-mapping  the same with another drive's default mapping (2 entries each way)
//   cable-damage  one second after OP, 5 frames are damaged on the cable into l_elbow's port 0: the
//             link diagnostics count them and warn, naming the cable; no joint is lost
//   rescue    the robot is initialized and the rescue RC task takes the motion (the runtime sends
//             "initialize robot" and `owner 0`): the approach to the ready posture (1.6 s), then
//             lowering, forwarding, backwarding (1 s each); 3 s after OP, in the forwarding phase,
//             the cable into l_elbow is cut; the motion goes on with the remaining joints; the run
//             stops cleanly 0.2 s after the motion's end (at most run_on after the cut,
//             docs/motion-owner.md)
//
// The scenario acts from the EtherCAT handler's thread, between two cycles (the simulated segment
// is driven by that thread's frames), and only on the simulated NIC.
#pragma once

#include <array>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/robot/robot.hpp"
#include "drivers/sim/segment/simulated_segment.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

enum class ScenarioKind : std::uint8_t { none, link_cut, rescue, power_cycle, cable_damage };

struct Scenario {
  ScenarioKind kind{ScenarioKind::none};
  const char* name{"none"};
  std::size_t cut_joint{kJointCount};   // link_cut: the joint whose incoming cable is cut; power_cycle: the joint
  hal::Nanoseconds cut_after_op{0};     // link_cut: how long after OP
  // rescue: the cut comes this long after the rescue motion entered its forwarding phase, whenever
  // that is (a loaded host stretches the motion in wall time: a cut at a fixed time after OP then
  // fell in the lowering); -1: by cut_after_op alone.
  hal::Nanoseconds cut_into_forwarding{-1};
  JointMask expected_lost{0};           // link_cut: what the firmware must report
  // power_cycle: the joints behind the power-cycled drive on its branch may miss the one frame that
  // first showed the shortfall: a working counter short by one slave cannot tell a slave out
  // mid-branch from a cut behind the last but one (the next frame's probes place it).
  JointMask may_miss_first_frame{0};
  // half-mapped, foreign-mapping: the drive's PDO mapping is left wrong before bring-up and again
  // before its power cycle.
  bool mapping_fault{false};
  drivers::PdoMappingFault fault{drivers::PdoMappingFault::half_written};
  hal::Nanoseconds run_on{0};           // after acting, the run goes on at most this long (without --duration)
  hal::Nanoseconds repeat_every{0};     // flaky-cable: the cable damaged again this often (0: once)
  bool rescue_motion{false};            // the rescue RC task takes the motion once the robot is initialized
  std::array<double, 3> motion_phase_s{};  // rescue: lowering, forwarding, backwarding (s)
};

// Parses --scenario (nullptr: none). Unknown names are an error naming the known ones.
Result<Scenario> parse_scenario(const char* name) noexcept;

// Drives a scenario: call after every cycle with the cycle's time and whether the master is in OP.
class ScenarioRunner {
 public:
  ScenarioRunner(const Scenario& scenario, drivers::SimulatedSegment* segment) noexcept
      : scenario_(scenario), segment_(segment) {}

  // Returns true in the cycle the scenario acted (the caller logs it). `rescue_forwarding`: the
  // rescue RC task published that its motion is in the forwarding phase.
  bool on_cycle(hal::Nanoseconds now, bool network_op, bool rescue_forwarding = false) noexcept;
  // Before bring-up: what the scenario does to the segment first (the drive's mapping left wrong).
  Status before_bring_up() noexcept;

  bool acted() const noexcept { return acted_; }
  hal::Nanoseconds acted_at() const noexcept { return acted_at_; }
  const Scenario& scenario() const noexcept { return scenario_; }
  const Status& action_status() const noexcept { return action_status_; }

 private:
  Scenario scenario_;
  drivers::SimulatedSegment* segment_;
  hal::Nanoseconds op_at_{-1};
  hal::Nanoseconds forwarding_since_{-1};
  bool acted_{false};
  hal::Nanoseconds acted_at_{0};
  hal::Nanoseconds last_repeat_{0};
  Status action_status_{};
};

}  // namespace rescue::app
