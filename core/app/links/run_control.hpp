// The run's own coordination, in the shared-memory segment with the tasks' data (TaskLinks::run):
// who is started, who should stop, and what each task reports at its end, so the supervisor can
// stop the tasks in order and print the run's figures whether the tasks are threads or processes.
// Every member is a lock-free atomic with one writer (named on each line).
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

#include "core/robot/robot.hpp"

namespace rescue::app {

// Per task process (StatTask slot): its pid and what it did after its init (item "0 heap, 0 page
// faults after init"). Written by the task at its end; restarts by the supervisor.
struct TaskHealth {
  std::atomic<std::int32_t> pid;
  std::atomic<std::uint32_t> restarts;              // supervisor
  // ctl tasks: the task's own thread (gettid, what `chrt -p` and `ps -L` show) and when its current
  // incarnation started (monotonic ns, 0: not started), both written by the task at its start.
  std::atomic<std::int32_t> tid;
  // Records of the segment the task refused as damaged (a field its writer never writes, a damaged
  // heartbeat: docs/shared-memory.md "Records: what each reader checks"), live, written by the task;
  // a restarted task process adds its own (runtime/segment_records_report.hpp).
  std::atomic<std::uint32_t> damaged_records;
  std::atomic<std::int64_t> started_ns;
  std::atomic<std::uint64_t> heap_allocations;      // after the task's init (its process's heap guard)
  std::atomic<std::uint64_t> page_faults;           // minor + major of the task's thread after its init
  std::atomic<bool> reported;                       // the figures above are final
};

// Every bounded queue between the tasks that may drop (or defer) a message, with its counter here,
// live: written only by the task at the queue's producing end, read by `ctl tasks` and the run's
// summary (docs/tasks.md, "Queues and what they drop"). Nothing the robot's correctness depends on
// travels through a queue that drops: these carry log lines, replies the operator is told to retry
// (busy), and the power-cycle hint the operator's clear replaces.
enum class DropCounter : std::uint8_t {
  events_dropped,               // EtherCAT handler -> its logger: handler events (log lines)
  reports_dropped,              // master's link monitor -> handler: link reports (log lines; the masks are state)
  warnings_dropped,             // master's link diagnostics -> handler: port warnings (log lines; ctl diag has the counters)
  capture_frames_dropped,       // handler's capture tap -> logger (--capture)
  power_cycle_reports_dropped,  // handler -> joint manager: "back after a power cycle" (no automatic clear; the operator's stays)
  joint_events_dropped,         // joint manager -> its logger: joint events (log lines; the states are in ctl status)
  outcomes_deferred,            // joint manager -> message parser: never dropped, kept and resent (commands wait)
  replies_dropped,              // message parser -> socket handler / runtime: replies (the operator's ctl times out)
  requests_dropped,             // socket handler -> message parser: requests answered busy
  local_requests_dropped,       // runtime (start-up, exit) -> message parser: said on stdout
};
constexpr std::size_t kDropCounters = 10;
constexpr const char* kDropCounterNames[kDropCounters] = {
    "events_dropped",       "reports_dropped",      "warnings_dropped", "capture_frames_dropped", "power_cycle_reports_dropped",
    "joint_events_dropped", "outcomes_deferred",    "replies_dropped",  "requests_dropped",       "local_requests_dropped"};

// One per StatTask (links/task_links.hpp): EtherCAT handler, joint manager, socket handler, message
// parser, RC rescue, RC teleop.
constexpr std::size_t kRunHealthSlots = 6;

struct RunControl {
  std::atomic<bool> stop;             // supervisor -> EtherCAT handler: stop the drives and end
  std::atomic<bool> operator_stop;    // supervisor -> socket handler, message parser: end
  std::atomic<bool> rc_stop;          // supervisor -> RC tasks: end
  std::atomic<bool> manager_stop;     // supervisor -> joint manager: end (after its last step)
  std::atomic<std::int32_t> tasks_started;  // each task, once past its real-time set-up
  // EtherCAT handler -> supervisor.
  std::atomic<bool> op;
  std::atomic<std::int64_t> op_at;
  std::atomic<std::int64_t> scenario_at;  // when the scenario acted (the handler's clock)
  std::atomic<std::uint64_t> cycles;
  std::atomic<bool> scenario_acted;
  std::atomic<bool> scenario_ok;      // the scenario's action happened and succeeded
  std::atomic<bool> handler_done;     // every figure of the handler below is final
  std::atomic<bool> drives_disabled;
  std::atomic<std::uint64_t> frames_missing;
  std::atomic<std::uint64_t> late_periods;     // as `ctl master` shows them (skipped ones included)
  std::atomic<std::uint64_t> skipped_periods;  // periods that had no cycle at all
  std::array<std::atomic<std::uint64_t>, kJointCount> missed_cycles;  // per joint
  // The ring (docs/redundancy.md), final once handler_done: its state (ecat::RingState, none without
  // a ring NIC), breaks and repairs, and the exchanges sent again after a repair in flight
  // (LinkStats::ring_repeats). Here, not read from the master, so that the run's summary has them
  // when the handler ran as a process of its own.
  std::atomic<std::uint8_t> ring_state;
  std::atomic<std::uint64_t> ring_breaks;
  std::atomic<std::uint64_t> ring_repairs;
  std::atomic<std::uint64_t> ring_repeats;
  // The handler's motion intake (motion/motion_intake.hpp), final once handler_done.
  std::atomic<std::uint64_t> intake_owned_periods;
  std::atomic<std::uint64_t> intake_used_periods;
  std::atomic<std::uint64_t> intake_misses;
  std::atomic<std::uint64_t> intake_releases;
  // What the intake sent each joint (MotionIntake::sent_figures): the largest speed, acceleration
  // and jerk, for the run's joint-limit verdict.
  std::array<std::atomic<double>, kJointCount> sent_max_speed_rad_s;
  std::array<std::atomic<double>, kJointCount> sent_max_acceleration_rad_s2;
  std::array<std::atomic<double>, kJointCount> sent_max_jerk_rad_s3;
  // Joint manager -> supervisor, final once manager_done.
  std::atomic<bool> manager_done;
  std::atomic<std::uint32_t> lost_joints;   // JointMask
  std::atomic<std::uint32_t> lost_since_start;  // JointMask: every joint marked lost, cleared since or not
  std::atomic<std::uint8_t> condition;      // fsm::RobotCondition
  std::atomic<bool> file_dirty;
  // Supervisor's liveness watch (runtime/liveness_watch.hpp) -> run summary: the tasks silent now
  // (bit k = StatTask k), silences reported, and the largest heartbeat age at a report.
  std::atomic<std::uint32_t> silent_tasks;
  std::atomic<std::uint64_t> silences_reported;
  std::atomic<std::int64_t> silence_report_age_max_ns;
  // Socket handler -> supervisor: the most datagrams one wake-up handled (budget: SocketHandler::kBudget).
  std::atomic<std::uint64_t> socket_max_per_wakeup;
  std::array<TaskHealth, kRunHealthSlots> health;         // StatTask order
  std::array<std::atomic<std::uint64_t>, kDropCounters> dropped;  // DropCounter order; live, one writer each
};

}  // namespace rescue::app
