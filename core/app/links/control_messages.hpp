// Records between the socket handler, the message parser, the joint manager, the RC tasks and the
// runtime (design brief section 3): fixed-size, trivially copyable, pointer-free, so they travel
// through the SPSC queues and seqlocks of TaskLinks whether the tasks are threads or processes.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <type_traits>

#include "core/app/links/joint_messages.hpp"
#include "core/app/links/protocol_messages.hpp"
#include "core/app/links/run_control.hpp"
#include "core/robot/joint_sample.hpp"
#include "core/robot/robot.hpp"

namespace rescue::app {

enum class RcInputKind : std::uint8_t { end_effector_target, hand, take_ownership };

// Message parser -> one RC task's input queue.
struct RcTaskInput {
  RcInputKind kind{RcInputKind::end_effector_target};
  std::uint8_t effector{0};        // protocol::Effector
  std::uint8_t action{0};          // protocol::HandAction
  std::array<double, 6> pose{};    // x, y, z (m), roll, pitch, yaw (rad), robot base frame
  std::uint64_t sequence{0};       // the operator's request
};
static_assert(std::is_trivially_copyable_v<RcTaskInput>, "queued as bytes");

// An authentic, decoded operator request (socket handler or runtime -> message parser).
struct ControlRequest {
  protocol::MessageType type{protocol::MessageType::get_status};
  std::uint32_t sender{0};
  std::uint64_t sequence{0};
  JointMask joints{0};
  ControlMode mode{ControlMode::none};
  std::uint8_t task{0};      // RC task index (move, hand, owner)
  RcTaskInput rc{};          // move, hand: what the RC task takes (effector, action, pose), passed on whole
  std::uint32_t reply_address{0};  // IPv4, network byte order (0: a local request)
  std::uint16_t reply_port{0};     // host byte order
};
static_assert(std::is_trivially_copyable_v<ControlRequest>, "queued as bytes");

// The parser's answer (message parser -> socket handler, or -> runtime for local requests).
struct ControlReply {
  std::uint32_t reply_address{0};
  std::uint16_t reply_port{0};
  std::uint32_t sender{0};
  std::uint64_t request_sequence{0};
  protocol::MessageType request_type{protocol::MessageType::get_status};
  protocol::Outcome outcome{protocol::Outcome::accepted};
  protocol::RefusalReason reason{protocol::RefusalReason::none};
  JointMask refused_joints{0};
  std::array<char, protocol::kReplyTextSize> text{};
  std::array<protocol::JointRefusalRecord, kJointCount> joint_refusals{};  // every blocking joint's own reason
};
static_assert(std::is_trivially_copyable_v<ControlReply>, "queued as bytes");

// Seqlock records are trivial (no member initialisers): value-initialise them.
// Sensor data from the two other robot computers (socket handler -> RC tasks), SI units.
struct SensorData {
  protocol::ImuRecord imu;
  std::int64_t imu_received_ns;  // monotonic time the socket handler took it; 0: none yet
  std::uint64_t imu_records;
  protocol::GpsRecord gps;
  std::int64_t gps_received_ns;
  std::uint64_t gps_records;
};
static_assert(std::is_trivial_v<SensorData>, "published through a seqlock");

// The socket handler's counters (published for ctl master and the run's summary).
struct SocketCounters {
  std::uint64_t datagrams;   // received, before any check
  std::uint64_t accepted;
  std::array<std::uint64_t, protocol::kRejectionCount> rejected;
  std::uint64_t replies_sent;
  std::uint64_t wakeups;
  std::uint64_t budget_exhausted;  // wake-ups that stopped at the per-wake-up budget
  std::uint64_t forwarded_dropped; // control requests the parser's full queue could not take
  std::array<std::uint64_t, 6> spare;  // 0: Seqlock<SocketCounters> 168 bytes keeps the next member on its cache line (TaskLinks' padding)
};
static_assert(std::is_trivial_v<SocketCounters>, "published through a seqlock");

// The EtherCAT handler's counters (for ctl master).
// The ring's state as the master judges it (cable redundancy, docs/redundancy.md "The ring state"),
// in the 8 bytes MasterStatus had spare: `ctl graph` draws it.
struct RingSummary {
  std::uint8_t state;       // ecat::RingState (0 none: no ring NIC)
  std::uint8_t before;      // open / lost: the last slave the main port reaches (ecat::kMainPort: none)
  std::uint8_t after;       // ... the first the ring port reaches (ecat::kRingPort: none)
  std::uint8_t transients;  // frames no evidence of a still ring (saturates at 255)
  std::uint16_t breaks;     // transitions out of closed (saturates)
  std::uint16_t repairs;    // transitions back to closed (saturates)
};
static_assert(sizeof(RingSummary) == 8, "in the place of MasterStatus' spare word");

struct MasterStatus {
  std::uint8_t state;  // ecat::MasterState
  std::uint64_t cycles;
  std::uint64_t frames_sent;
  std::uint64_t frames_lost;
  std::uint64_t late_periods;
  std::int64_t dc_deviation_ns;
  std::int64_t dc_max_deviation_ns;
  std::uint64_t in_exchange;  // slave mask
  std::uint64_t lost;         // slave mask
  // Online recovery per slave (position): its state (ecat::RecoveryState) and how long ago, in ms,
  // it last changed (protocol::kRecoveryAgeNever: not since bring-up), as of this publication.
  std::array<std::uint8_t, protocol::kMaxSlaves> recovery;
  std::array<std::uint32_t, protocol::kMaxSlaves> recovery_age_ms;
  // 8 bytes: Seqlock<MasterStatus> grew by 128 bytes (2 cache lines), so TaskLinks keeps its members on their lines
  RingSummary ring;
};
static_assert(std::is_trivial_v<MasterStatus>, "published through a seqlock");

// ctl diag --reset (TaskLinks::diag_reset): the socket handler (its only writer) posts a request, the
// EtherCAT handler polls it once per period (a load, never a wait), zeroes the counters of those
// slaves in its master, publishes the zeroed table and then stores the request's generation in
// `done`: the socket handler answers the operator when `done` reaches it.
struct DiagResetLink {
  static constexpr std::uint64_t kMaskBits = 0xFFFFFFFFU;
  // (generation << 32) | slave mask; generation 0: nothing asked yet. A request the handler has not
  // taken yet is widened (its mask ORed in), never lost.
  std::atomic<std::uint64_t> requested;
  std::atomic<std::uint64_t> done;  // generation of the latest request applied and published
  static constexpr std::uint64_t generation_of(std::uint64_t word) noexcept { return word >> 32; }
  static constexpr std::uint32_t slaves_of(std::uint64_t word) noexcept { return static_cast<std::uint32_t>(word & kMaskBits); }
};
static_assert(std::atomic<std::uint64_t>::is_always_lock_free, "shared between processes");

// One task's timing (each task writes its own).
struct TaskStat {
  std::array<char, protocol::kNameSize> name;
  std::int32_t pid;
  std::int16_t cpu;       // the task table's (the CPU it asked for, on this machine)
  std::int16_t priority;  // the task table's (SCHED_FIFO priority it asked for, 0: normal)
  std::uint64_t periods;
  std::uint64_t missed;
  std::uint64_t max_execution_ns;
  TimingFigures execution;  // the task's PeriodRecorder, published every few periods
  TimingFigures latency;
  // What the kernel reports for the task's thread, read by the task itself at each publication
  // (hal::thread_schedule): these 8 bytes keep Seqlock<TaskStat> at 128 bytes (cache-line multiples).
  std::int8_t kernel_policy;     // SCHED_OTHER 0, SCHED_FIFO 1, ...; -1 unknown
  std::int8_t reserved;
  std::int16_t kernel_priority;  // sched_getparam
  std::int16_t kernel_cpu;       // sched_getcpu: where it ran at the publication
  std::int16_t reserved2;
};
static_assert(std::is_trivial_v<TaskStat>, "published through a seqlock");

// The one conversion between the wire's messages and the tasks' records, one function per record
// (used wherever that record meets the wire).
// An authentic, decoded request (`m`) from reply_address:reply_port -> the parser's record; the
// operator's pose is converted here, once, into the RC task's input form.
inline ControlRequest request_of(const protocol::Message& m, std::uint32_t reply_address, std::uint16_t reply_port) noexcept {
  ControlRequest r;
  r.type = m.header.type;
  r.sender = m.header.sender;
  r.sequence = m.header.sequence;
  r.joints = m.joints.joints;
  r.mode = m.joints.mode;
  if (m.header.type == protocol::MessageType::move_effector) {
    r.task = m.move.task;
    r.rc.effector = static_cast<std::uint8_t>(m.move.effector);
    for (std::size_t i = 0; i < 3; ++i) {
      r.rc.pose[i] = m.move.position_m[i];
      r.rc.pose[i + 3] = m.move.rpy_rad[i];
    }
  } else if (m.header.type == protocol::MessageType::hand) {
    r.task = m.hand.task;
    r.rc.effector = static_cast<std::uint8_t>(m.hand.hand);
    r.rc.action = static_cast<std::uint8_t>(m.hand.action);
  } else if (m.header.type == protocol::MessageType::take_owner) {
    r.task = m.owner.task;
  }
  r.reply_address = reply_address;
  r.reply_port = reply_port;
  return r;
}

// The parser's answer -> the reply message to send.
inline protocol::Message message_of(const ControlReply& reply) noexcept {
  protocol::Message m;
  m.header.type = protocol::MessageType::reply;
  m.reply.request_sequence = reply.request_sequence;
  m.reply.request_type = reply.request_type;
  m.reply.outcome = reply.outcome;
  m.reply.reason = reply.reason;
  m.reply.refused_joints = reply.refused_joints;
  m.reply.text = reply.text;
  m.reply.joint_refusals = reply.joint_refusals;
  return m;
}

// The EtherCAT handler's published counters -> the master answer. How old they are (`age`) and the
// socket handler's own counters (datagrams accepted, rejected) are the answerer's to add.
inline protocol::MasterPayload master_payload_of(const MasterStatus& s) noexcept {
  protocol::MasterPayload p;
  p.state = s.state;
  p.cycles = s.cycles;
  p.frames_sent = s.frames_sent;
  p.frames_lost = s.frames_lost;
  p.late_periods = s.late_periods;
  p.dc_deviation_ns = s.dc_deviation_ns;
  p.dc_max_deviation_ns = s.dc_max_deviation_ns;
  return p;
}

// One task's published timing -> its record in the tasks answer: where the kernel ran it, at what
// policy and priority, beside what the task table asked for; from its health slot (nullptr: none),
// its thread, restarts and uptime at `now_ns` (the monotonic clock of TaskHealth::started_ns).
inline protocol::TaskRecord task_record_of(const TaskStat& t, const TaskHealth* health, std::int64_t now_ns) noexcept {
  protocol::TaskRecord r;
  r.name = t.name;
  r.pid = t.pid;
  r.uptime_ms = protocol::kUptimeUnknown;
  if (health != nullptr) {
    r.tid = health->tid.load(std::memory_order_relaxed);
    const std::uint32_t restarts = health->restarts.load(std::memory_order_relaxed);
    r.restarts = static_cast<std::uint16_t>(restarts > 0xFFFFU ? 0xFFFFU : restarts);
    const std::int64_t started = health->started_ns.load(std::memory_order_acquire);
    if (started > 0) {
      const std::int64_t ms = (now_ns > started ? now_ns - started : 0) / 1000000;
      r.uptime_ms = ms >= protocol::kUptimeSaturated ? protocol::kUptimeSaturated : static_cast<std::uint32_t>(ms);
    }
  }
  r.cpu = t.kernel_cpu;
  r.priority = t.kernel_priority;
  r.policy = t.kernel_policy;
  r.table_cpu = t.cpu;
  r.table_priority = t.priority;
  r.periods = t.periods;
  r.missed = t.missed;
  r.max_execution_ns = t.max_execution_ns;
  r.execution = t.execution;
  r.latency = t.latency;
  return r;
}

// One joint's status (the joint manager's) and values (the EtherCAT handler's) -> its record in the
// status answer; either may not be published yet (nullptr). `owner`: the RC task whose references
// drive it (protocol::kNoOwner: none).
inline protocol::JointStatusRecord joint_status_record_of(const PublishedJointStatus* status, const JointSample* sample,
                                                          std::uint8_t owner) noexcept {
  protocol::JointStatusRecord r;
  if (status != nullptr) {
    r.state = static_cast<std::uint8_t>(status->state);
    r.mode = static_cast<std::int8_t>(status->mode);
    r.fault = static_cast<std::uint8_t>(status->fault);
    if (status->drive_enabled) r.flags |= protocol::kFlagDriveEnabled;
    if (status->lost) r.flags |= protocol::kFlagLost;
  }
  if (sample != nullptr) {
    if (sample->reachable) r.flags |= protocol::kFlagReachable;
    if (sample->drive_fault) r.flags |= protocol::kFlagDriveFault;
    r.position_rad = sample->position_rad;
    r.velocity_rad_s = sample->velocity_rad_s;
    r.torque_nm = sample->torque_nm;
  }
  r.owner = owner;
  return r;
}

}  // namespace rescue::app
