// `rescue-motion run`: the firmware's tasks as threads of one process (the design brief's
// simulation/test mode; the same task code runs as processes over shared memory):
//
//   main thread       start-up, then the logger: prints what the tasks queue, the operator's
//                     pre-defined "initialize robot" message once the network is in OP
//   joint manager     CPU thread 2, SCHED_FIFO 70: DFA, limit monitoring, reconfiguration, file
//   EtherCAT handler  CPU thread 3, SCHED_FIFO 80: one frame per millisecond
//
// Start-up order (design brief section 6): the error-joints file is read before the network
// comes up; the master then expects the joints it lists to be absent, except those the operator
// declares repaired (--clear-joint): they must answer at bring-up, and once they do in OP the
// joint manager clears them (one durable write, logged) and resets them to Idle.
#pragma once

#include <cstdint>

#include "core/app/cli/nic_option.hpp"
#include "core/app/sim/run_scenario.hpp"
#include "core/robot/robot.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

struct FirmwareOptions {
  NicChoice nic{};
  const char* nic_text{"sim"};
  Scenario scenario{};
  hal::Nanoseconds duration{0};      // 0: until SIGINT/SIGTERM (or the scenario's own end)
  const char* capture_path{nullptr};
  const char* timing_out{nullptr};   // directory: per-period timing of the tasks written there at the end
  const char* state_dir{nullptr};    // nullptr: the default (hal::resolve_state_dir)
  bool initialize{false};            // send "initialize robot" once the network is in OP
  JointMask clear_joints{0};         // operator: these lost joints were repaired (clear them once they answer)
};

// Runs until the duration, the scenario's end or a stop signal; returns the exit status.
int run_firmware(const FirmwareOptions& options) noexcept;

}  // namespace rescue::app
