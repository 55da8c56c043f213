// The runner's shared context (internal to core/app/runtime): the objects run_firmware wires once before
// the tasks start, read by the task loops, the logger's passes, the two task modes and the end-of-run
// report. Only core/app/runtime/*.cpp include it.
#pragma once

#include <atomic>
#include <cstddef>

#include "core/app/config/firmware_config.hpp"
#include "core/app/links/task_links.hpp"
#include "core/app/operator_protocol/replay_window.hpp"
#include "core/app/runtime/firmware.hpp"
#include "core/app/runtime/task_ports.hpp"
#include "core/app/shm/shared_segment.hpp"
#include "core/app/sim/run_scenario.hpp"
#include "core/app/tasks/error_joints_worker.hpp"
#include "core/app/tasks/ethercat_handler.hpp"
#include "core/app/tasks/joint_event_printer.hpp"
#include "core/app/tasks/joint_event_queue.hpp"
#include "core/app/tasks/joint_manager.hpp"
#include "core/app/tasks/message_parser.hpp"
#include "core/app/tasks/rescue_task.hpp"
#include "core/app/tasks/teleop_task.hpp"
#include "core/app/tasks/socket_handler.hpp"
#include "ecat/capture/capture_queue.hpp"
#include "ecat/capture/capture_writer.hpp"
#include "hal/rt/rt_setup.hpp"
#include "hal/time/clock.hpp"
#include "hal/time/wall_clock.hpp"

namespace rescue::app::runner {

constexpr hal::Nanoseconds kLoggerPeriod = config::kLoggerPeriodNs;
constexpr hal::Nanoseconds kDisableTimeout = config::kDisableTimeoutNs;
constexpr std::size_t kCaptureFramesPerLoggerPass = 256;

// What the tasks run on: the static objects run_firmware wires once, before the tasks start (a
// forked task process finds them at the same addresses).
struct TaskSet {
  EthercatHandler* handler;
  ScenarioRunner* scenario;
  JointManager* manager;
  MessageParser* parser;
  SocketHandler* socket;
  RescueTask* rc_rescue;
  TeleopTask* rc_teleop;
  protocol::ReplayWindow* replay;
  hal::WallClock* wall_clock;
  hal::Clock* clock;           // the NIC's: the handler's and the joint manager's
  hal::Clock* operator_clock;  // the socket handler's and the message parser's
  const FirmwareOptions* options;
  bool operator_port;
  hal::Nanoseconds start;
  JointEventQueue* joint_events;          // the joint manager's events (its process's or thread's)
  JointEventPrinter* joint_event_printer;  // printed by the joint manager's logger
  // The error-joints file's writer: a normal-priority thread of the joint manager's process.
  ErrorJointsStorageWorker* storage_worker;
  // Every task's ports (task_ports.hpp): the task loops take theirs from here (TaskPorts::task_loop).
  TaskPorts* ports;
};

// One instance in the whole program (g_run): its padding costs some bytes once, and the members stay in
// the order that explains them.
struct RunContext {  // NOLINT(clang-analyzer-optin.performance.Padding)
  // What the tasks share lives in the shared-memory segment (docs/shared-memory.md), created once per
  // process at start-up (a second run_firmware in the same process, as tests do, reuses it).
  shm::SegmentOwner segment;
  ecat::CaptureWriter capture;
  // The handler's tap only copies frames into this queue; the logger thread writes them (the disk
  // may block, the 1 ms cycle must not).
  ecat::CaptureQueue capture_queue;
  TaskSet tasks{};
  // Joint manager -> its storage worker (same process): end once the last write is done.
  std::atomic<bool> storage_stop{false};
  // Whether the tasks run as processes (the default) or threads of one process (--threads).
  bool task_processes{false};
  // The start-up thread's own scheduling, given back right after the EtherCAT handler's process is
  // forked (which so inherits the handler's priority and CPU, and never waits behind the host's
  // other load before it raises them itself); nullptr: nothing to give back.
  const hal::SchedulingState* start_up_scheduling{nullptr};
};
// Process-wide on purpose: a forked task process finds it at the same address, and the task entry
// points (std::thread's, the supervisor's) take no argument. Defined in run_context.cpp.
extern RunContext g_run;

// The segment's TaskLinks and RunControl, named for what they are (the tasks themselves see only
// their ports, task_ports.hpp; these serve the runner's own loops and report).
inline TaskLinks& shared_links() noexcept { return g_run.segment.links(); }

// How many tasks run: the socket handler only with the operator's port (a key file).
inline int task_count() noexcept { return g_run.tasks.operator_port ? 6 : 5; }

// The run's coordination lives in the segment too (core/app/links/run_control.hpp): the same code
// stops and reports the tasks whether they are threads or processes.
inline RunControl& run_control() noexcept { return shared_links().run; }

// One pass of the per-task CPU meter (runtime/task_cpu.hpp) over this process and the task
// processes, from the logger's or the supervisor's loop (a normal thread): `done` once the handler ended.
void observe_task_cpu(hal::Clock& clock, bool done) noexcept;

using hal::seconds;  // hal/time/clock.hpp

}  // namespace rescue::app::runner
