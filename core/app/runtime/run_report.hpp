// The end of a run (docs/firmware.md, step 5): the figures the tasks published in the segment, the
// scenario's verdict, the `key: value` summary lines, and the exit status of a run that stopped in order.
#pragma once

#include <cstdint>

#include "core/app/links/task_links.hpp"
#include "core/app/runtime/firmware.hpp"
#include "core/app/sim/run_scenario.hpp"
#include "core/app/tasks/motion_intake.hpp"
#include "core/app/tasks/socket_handler.hpp"
#include "ecat/master/master.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app::runner {

// Step 5: the run's figures, from what the tasks published in the segment (run_control.hpp), also into
// options.report; returns the cycles healthy joints missed.
std::uint64_t print_run_figures(const FirmwareOptions& options, const SocketHandler& socket) noexcept;

// A scenario's checks once the run stopped: 0, or the exit status after saying what failed.
// What the tasks reported is read from the segment (run_control.hpp): threads or processes alike.
// Exit status of a scenario's run: 0 when it did what the scenario promises (run_scenario.hpp).
int scenario_verdict(const Scenario& wanted, const RunControl& state, JointMask lost, JointMask restored,
                     bool auto_clear_power_cycled, std::uint8_t rescue_phase_reached) noexcept;

// The joints in Error at the end that are not `excused` (lost by the scenario's cut, or restored in
// Error from the error-joints file): a scenario with any of them failed, whatever else held.
JointMask joints_ended_in_error(const RobotJointStatus& ended, JointMask excused) noexcept;

// The run's figures as `key: value` lines (the last lines of every run), docs/motion-owner.md.
// Per task: what it published in its timing slot and its health slot (run_control.hpp).
struct RunSummary {
  std::uint64_t cycles{0};
  std::uint64_t heap_allocations{0};
  JointMask lost{0};
  const SocketCounters* socket{nullptr};
  MotionIntakeCounters intake{};
  std::uint8_t rescue_phase_reached{0};
  bool processes{false};
  hal::Nanoseconds start{0};                      // the run's clock origin (NIC open)
  const ecat::BringUpReport* bring_up{nullptr};   // the bring-up's report (time to SAFE-OP, SII cache hits)
  std::uint64_t supervisor_damaged_beats{0};      // the liveness watch's damaged heartbeats (segment_records_report.hpp)
};

void print_run_summary(const RunSummary& s) noexcept;

// The exit status of a run that stopped in order, said on stderr when it is not 0.
int robot_exit(fsm::RobotCondition condition) noexcept;

// The joint-limit verdict over every reference the EtherCAT handler sent (MotionIntake's figures,
// final once handler_done): `sent_worst_*_ratio` and `joint_limits: within|exceeded` lines; 0, or
// kExitJointLimit with one line on stderr per limit exceeded (the joint, the figure, the limit).
int sent_joint_limits_exit(const RunControl& state) noexcept;

}  // namespace rescue::app::runner
