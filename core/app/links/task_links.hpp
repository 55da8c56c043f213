// What the tasks of the firmware share (design brief section 3): the EtherCAT handler's published
// joint values, the joint manager's published drive demand, and the bounded queues between them.
// Every member is a lock-free, pointer-free, standard-layout object (Seqlock, SpscQueue), so this
// record can live in static storage when the tasks are threads of one process (`run`) or in a
// POSIX shared-memory segment when they are processes.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <type_traits>

#include "core/app/config/firmware_config.hpp"
#include "core/app/links/control_messages.hpp"
#include "core/app/links/joint_messages.hpp"
#include "core/app/motion/motion_links.hpp"
#include "core/robot/joint_demand.hpp"
#include "core/robot/joint_sample.hpp"
#include "core/robot/robot.hpp"
#include "core/concurrency/seqlock.hpp"
#include "core/concurrency/spsc_queue.hpp"

namespace rescue::app {

// The tasks that publish their timing (TaskLinks::task_stats), in this order.
enum class StatTask : std::uint8_t {
  ethercat_handler = 0, joint_manager = 1, socket_handler = 2, message_parser = 3, rc_rescue = 4, rc_teleop = 5
};
constexpr std::size_t kTaskStatSlots = 6;

struct TaskLinks {
  static constexpr std::uint32_t kLayoutVersion = 4;
  static constexpr std::size_t kReportQueueDepth = config::kLostReportQueueDepth;
  static constexpr std::size_t kNoticeQueueDepth = config::kNoticeQueueDepth;
  static constexpr std::size_t kCommandQueueDepth = config::kJointCommandQueueDepth;
  static constexpr std::size_t kRequestQueueDepth = 16;
  static constexpr std::size_t kReplyQueueDepth = 16;
  static constexpr std::size_t kOutcomeQueueDepth = 64;
  static constexpr std::size_t kRcInputQueueDepth = 8;

  std::uint32_t layout_version{kLayoutVersion};
  Seqlock<RobotSample> samples;                                   // handler -> joint manager, RC tasks
  Seqlock<RobotDemand> demand;                                    // joint manager -> handler
  SpscQueue<LostJointsReport, kReportQueueDepth> lost_reports;    // handler -> joint manager (step 1)
  SpscQueue<JointManagerNotice, kNoticeQueueDepth> notices;       // joint manager -> handler (step 4)
  SpscQueue<JointCommand, kCommandQueueDepth> joint_commands;     // message parser -> joint manager (its only producer)
  // The operator's path in (docs/protocol.md, docs/operator.md).
  Seqlock<RobotJointStatus> joint_status;                         // joint manager -> socket handler (status), parser
  Seqlock<MasterStatus> master_status;                            // EtherCAT handler's loop -> socket handler
  Seqlock<protocol::DiagPayload> link_diag;                       // EtherCAT handler's loop -> socket handler (per sweep)
  Seqlock<SensorData> sensors;                                    // socket handler -> RC tasks (IMU, GPS)
  Seqlock<SocketCounters> socket_counters;                        // socket handler -> status, run summary
  std::array<Seqlock<TaskStat>, kTaskStatSlots> task_stats;       // each task its own slot (StatTask)
  SpscQueue<ControlRequest, kRequestQueueDepth> control_requests; // socket handler -> message parser
  SpscQueue<ControlReply, kReplyQueueDepth> control_replies;      // message parser -> socket handler
  SpscQueue<ControlRequest, kRequestQueueDepth> local_requests;   // runtime (start-up, exit) -> message parser
  SpscQueue<ControlReply, kReplyQueueDepth> local_replies;        // message parser -> runtime
  SpscQueue<JointCommandOutcome, kOutcomeQueueDepth> command_outcomes;  // joint manager -> message parser
  // Per RC task: its input queue (parser -> task k) and its heartbeat, the monotonic time (ns) of
  // its latest period, 0 before its first (tasks/rc_task.hpp writes it; the parser and the
  // handler's motion intake read it).
  std::array<SpscQueue<RcTaskInput, kRcInputQueueDepth>, protocol::kMaxRcTasks> rc_inputs;
  std::array<std::atomic<std::int64_t>, protocol::kMaxRcTasks> rc_heartbeat_ns{};
  // The RC tasks' reference spaces and the Motion owner (core/app/motion/, docs/motion-owner.md).
  MotionLinks motion;
};
static_assert(std::is_standard_layout_v<TaskLinks>, "shared between processes: standard layout only");

}  // namespace rescue::app
