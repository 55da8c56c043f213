// `rescue-motion run`: the firmware's tasks as threads of one process (the design brief's
// simulation/test mode; the same task code runs as processes over shared memory):
//
//   main thread       start-up, then the logger: prints what the tasks queue, the operator's
//                     pre-defined "initialize robot" message once the network is in OP
//   joint manager     CPU thread 2, SCHED_FIFO 70: DFA, limit monitoring, reconfiguration, file
//   socket handler    CPU thread 1, normal priority: UDP control and sensor ports (docs/protocol.md)
//   message parser    CPU thread 1, normal priority: requests -> joint handle queue, RC-task inputs
//   EtherCAT handler  CPU thread 3, SCHED_FIFO 80: one frame per millisecond
//
// Start-up order (design brief section 6): the error-joints file is read before the network
// comes up; the master then expects the joints it lists to be absent, except those the operator
// declares repaired (--clear-joint): they must answer at bring-up, and once they do in OP the
// joint manager clears them (one durable write, logged) and resets them to Idle.
#pragma once

#include <array>
#include <cstdint>

#include "core/app/config/nic_option.hpp"
#include "core/app/sim/run_scenario.hpp"
#include "core/robot/robot.hpp"
#include "fsm/machines/joint_status_dfa.hpp"
#include "core/app/config/firmware_config.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

struct FirmwareOptions {
  NicChoice nic{};
  const char* nic_text{"sim"};
  // --ring-nic: the second master port (cable redundancy); nullptr text: none.
  NicChoice ring_nic{};
  const char* ring_nic_text{nullptr};
  Scenario scenario{};
  hal::Nanoseconds duration{0};      // 0: until SIGINT/SIGTERM (or the scenario's own end)
  // Bring-up gives up when no frame has come back for this long (exit status 1); 0: keeps trying.
  hal::Nanoseconds first_contact_limit{5 * hal::kNsPerSec};
  const char* capture_path{nullptr};
  const char* timing_out{nullptr};   // directory: per-period timing of the tasks written there at the end
  const char* state_dir{nullptr};    // nullptr: the default (hal::resolve_state_dir)
  const char* segment_name{nullptr}; // shared-memory segment; nullptr: derived from the state directory (docs/shared-memory.md)
  bool threads{false};               // the tasks as threads of one process (default: processes, docs/tasks.md)
  bool initialize{false};            // send "initialize robot" once the network is in OP
  JointMask clear_joints{0};         // operator: these lost joints were repaired (clear them once they answer)
  bool auto_clear_power_cycled{false};  // a joint whose drive was power-cycled and recovered is cleared automatically
  // The operator's path in (docs/protocol.md): UDP ports, and the pre-shared key file.
  const char* listen{"0.0.0.0"};
  std::uint16_t control_port{47010};
  std::uint16_t sensor_port{47011};
  const char* key_path{nullptr};     // nullptr: <state dir>/operator.key; absent there: no socket handler
  std::uint32_t robot_id{1};         // this robot's identity in every datagram (--robot-id, robot_id; docs/protocol.md)
  // A real-time task that completed no period for this long is reported (docs/tasks.md "Liveness"),
  // and `ctl status`, `slaves`, `master` mark the handler's figures stale.
  hal::Nanoseconds task_silent_after{config::kTaskSilentAfterNs};
  struct Report* report{nullptr};    // filled at the end, for in-process tests (may be nullptr)
};

// What a run did, for tests that run the firmware in-process.
struct Report {
  std::uint64_t cycles{0};
  std::uint64_t healthy_missed{0};   // cycles whose frame came back but missed a healthy joint
  std::uint64_t frames_missing{0};   // frames late or lost (host jitter)
  std::uint64_t datagrams{0};
  std::uint64_t accepted{0};
  std::array<std::uint64_t, 8> rejected{};  // per protocol::Rejection
  std::uint16_t control_port{0};
  std::uint16_t sensor_port{0};
};

// Exit status of a run that stopped in order: 0, except kExitRobotError when the robot ended in
// error (every joint in Error): a script or supervisor must never read that as success.
constexpr int kExitRobotError = 3;
// A reference was sent beyond a joint's speed, acceleration or jerk limit (a defect of the limits:
// every reference passes the same limiter, docs/kinematics.md): never read as success either.
constexpr int kExitJointLimit = 5;
int exit_status_for(fsm::RobotCondition condition) noexcept;

// Runs until the duration, the scenario's end or a stop signal; returns the exit status.
int run_firmware(const FirmwareOptions& options) noexcept;

}  // namespace rescue::app
