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
#include "core/app/links/motion_links.hpp"
#include "core/app/links/register_messages.hpp"
#include "core/app/links/rescan_messages.hpp"
#include "core/app/links/run_control.hpp"
#include "core/app/links/sdo_messages.hpp"
#include "core/app/links/slave_state_messages.hpp"
#include "core/concurrency/seqlock.hpp"
#include "core/concurrency/spsc_queue.hpp"
#include "core/robot/joint_demand.hpp"
#include "core/robot/joint_sample.hpp"
#include "core/robot/robot.hpp"

namespace rescue::app {

// The tasks that publish their timing (TaskLinks::task_stats), in this order.
enum class StatTask : std::uint8_t {
  ethercat_handler = 0, joint_manager = 1, socket_handler = 2, message_parser = 3, rc_rescue = 4, rc_teleop = 5
};
constexpr std::size_t kTaskStatSlots = 6;
static_assert(kTaskStatSlots == kRunHealthSlots, "one health slot per StatTask (run_control.hpp)");
// TaskLinks::task_heartbeat_ns: one slot per StatTask, rounded up to a cache line of int64 (the two
// spare slots stay 0) so that the queue after it needs no padding.
constexpr std::size_t kHeartbeatSlots = 8;
static_assert(kHeartbeatSlots >= kTaskStatSlots, "one heartbeat per StatTask");

// THE member list of TaskLinks, in layout order: X(name, "who writes -> who reads", type). The
// record's members, the segment's layout table and hash (core/app/shm/segment_layout.hpp) and the
// byte map of docs/shared-memory.md all come from this one list: adding a member is one line here.
// Every type must be lock-free, pointer-free and standard-layout (it lives in shared memory). The
// order keeps padding low (the static analysis checks it): rc_heartbeat_ns fills the gap before the
// first cache-line-aligned queue.
#define RESCUE_TASK_LINKS_MEMBERS(X)                                                                                   \
  X(samples, "EtherCAT handler -> joint manager, RC tasks, parser, socket handler", Seqlock<RobotSample>)              \
  X(demand, "joint manager -> EtherCAT handler", Seqlock<RobotDemand>)                                                \
  X(rc_heartbeat_ns, "RC task k -> message parser (monotonic ns of its latest period, 0 before its first)", std::array<std::atomic<std::int64_t>, protocol::kMaxRcTasks>) \
  X(task_heartbeat_ns, "each task its own slot (StatTask) -> supervisor (liveness), socket handler (age of figures) (monotonic ns at the end of its latest period, 0 before its first)", std::array<std::atomic<std::int64_t>, kHeartbeatSlots>) \
  X(lost_reports, "EtherCAT handler -> joint manager (step 1)", SpscQueue<LostJointsReport, kReportQueueDepth>)        \
  X(notices, "joint manager -> EtherCAT handler (step 4)", SpscQueue<JointManagerNotice, kNoticeQueueDepth>)            \
  X(joint_commands, "message parser (only producer) -> joint manager", SpscQueue<JointCommand, kCommandQueueDepth>)    \
  X(joint_status, "joint manager -> socket handler (status), message parser", Seqlock<RobotJointStatus>)               \
  X(master_status, "EtherCAT handler -> socket handler", Seqlock<MasterStatus>)                                       \
  X(link_diag, "EtherCAT handler (once per diagnostics sweep) -> socket handler (ctl diag)", Seqlock<protocol::DiagPayload>) \
  X(slave_info, "EtherCAT handler (at OP and when a slave's AL status changes) -> socket handler (ctl slaves -v)", Seqlock<protocol::SlaveInfoTable>) \
  X(diag_reset, "socket handler (ctl diag --reset) -> EtherCAT handler (polled once per period) -> done", DiagResetLink) \
  X(sensors, "socket handler -> RC tasks (IMU, GPS)", Seqlock<SensorData>)                                            \
  X(socket_counters, "socket handler -> status, run summary", Seqlock<SocketCounters>)                                \
  X(task_stats, "each task its own slot (StatTask) -> socket handler (ctl tasks)", std::array<Seqlock<TaskStat>, kTaskStatSlots>) \
  X(control_requests, "socket handler -> message parser", SpscQueue<ControlRequest, kRequestQueueDepth>)              \
  X(control_replies, "message parser -> socket handler", SpscQueue<ControlReply, kReplyQueueDepth>)                   \
  X(local_requests, "runtime (start-up, exit) -> message parser", SpscQueue<ControlRequest, kRequestQueueDepth>)      \
  X(local_replies, "message parser -> runtime", SpscQueue<ControlReply, kReplyQueueDepth>)                            \
  X(command_outcomes, "joint manager -> message parser", SpscQueue<JointCommandOutcome, kOutcomeQueueDepth>)          \
  X(rc_inputs, "message parser -> RC task k (its input queue)", std::array<SpscQueue<RcTaskInput, kRcInputQueueDepth>, protocol::kMaxRcTasks>) \
  X(sdo_requests, "socket handler -> EtherCAT handler (ctl upload/download, one in flight)", SpscQueue<SdoLinkRequest, config::kSdoQueueDepth>) \
  X(sdo_results, "EtherCAT handler -> socket handler (the transfer's end)", SpscQueue<SdoLinkResult, config::kSdoQueueDepth>) \
  X(reg_requests, "socket handler -> EtherCAT handler (ctl reg_read, one in flight)", SpscQueue<RegReadLinkRequest, config::kRegQueueDepth>) \
  X(reg_results, "EtherCAT handler -> socket handler (the read's end)", SpscQueue<RegReadLinkResult, config::kRegQueueDepth>) \
  X(states_requests, "socket handler -> EtherCAT handler (ctl states, one in flight)", SpscQueue<StatesLinkRequest, config::kStatesQueueDepth>) \
  X(states_results, "EtherCAT handler -> socket handler (the states request's end)", SpscQueue<StatesLinkResult, config::kStatesQueueDepth>) \
  X(rescan_requests, "socket handler -> EtherCAT handler (ctl rescan, one in flight)", SpscQueue<RescanLinkRequest, config::kRescanQueueDepth>) \
  X(rescan_results, "EtherCAT handler -> socket handler (the rescan's end)", SpscQueue<RescanLinkResult, config::kRescanQueueDepth>) \
  X(sii_images, "EtherCAT handler (after bring-up, one slave per period) -> socket handler (ctl sii_read)", std::array<Seqlock<SiiImageRecord>, protocol::kMaxSlaves>) \
  X(motion, "RC task k -> its reference space; owner word (CAS); EtherCAT handler's intake (motion_links.hpp)", MotionLinks) \
  X(run, "supervisor <-> every task: start, stop, end-of-run figures (run_control.hpp)", RunControl)

struct TaskLinks {
  static constexpr std::uint32_t kLayoutVersion = 13;  // bump on any change of meaning (the hash covers offsets and sizes)
  static constexpr std::size_t kReportQueueDepth = config::kLostReportQueueDepth;
  static constexpr std::size_t kNoticeQueueDepth = config::kNoticeQueueDepth;
  static constexpr std::size_t kCommandQueueDepth = config::kJointCommandQueueDepth;
  static constexpr std::size_t kRequestQueueDepth = config::kOperatorRequestQueueDepth;
  static constexpr std::size_t kReplyQueueDepth = config::kOperatorReplyQueueDepth;
  static constexpr std::size_t kOutcomeQueueDepth = config::kCommandOutcomeQueueDepth;
  static constexpr std::size_t kRcInputQueueDepth = config::kRcInputQueueDepth;

#define RESCUE_TASK_LINKS_X(name, who, ...) __VA_ARGS__ name{};
  RESCUE_TASK_LINKS_MEMBERS(RESCUE_TASK_LINKS_X)
#undef RESCUE_TASK_LINKS_X
};
static_assert(std::is_standard_layout_v<TaskLinks>, "shared between processes: standard layout only");
static_assert((sizeof(Seqlock<protocol::SlaveInfoTable>) + sizeof(DiagResetLink)) % 64 == 0,
              "slave_info and diag_reset together fill whole cache lines (no padding after them)");

}  // namespace rescue::app
