#include "core/app/operator_protocol/protocol_codec.hpp"

#include <cmath>
#include <cstring>

#include "core/base/endian.hpp"
#include "fsm/machines/joint_status_dfa.hpp"

namespace rescue::app::protocol {
namespace {

// Payload sizes (docs/protocol.md).
constexpr std::size_t kJointsSize = 4;
constexpr std::size_t kSelectModeSize = 8;
constexpr std::size_t kMoveSize = 56;
constexpr std::size_t kHandSize = 4;
constexpr std::size_t kOwnerSize = 4;
constexpr std::size_t kImuSize = 88;
constexpr std::size_t kGpsSize = 56;
constexpr std::size_t kReplySize = 16 + kReplyTextSize + 4 * kJointCount;  // + per joint: why, state, input, 0
constexpr std::size_t kStatusHeadSize = 16;
constexpr std::size_t kJointRecordSize = 32;
constexpr std::size_t kStatusSize = kStatusHeadSize + kJointCount * kJointRecordSize;
constexpr std::size_t kListHeadSize = 8;
constexpr std::size_t kSlaveRecordSize = 32;
constexpr std::size_t kMasterSize = 64 + kRejectionCount * 8;
constexpr std::size_t kEpochSize = 8;
constexpr std::size_t kTimingFiguresSize = 28;  // 7 x u32 ns
constexpr std::size_t kTaskRecordSize = 64 + 2 * kTimingFiguresSize;  // + policy, table CPU and priority
constexpr std::size_t kDiagHeadSize = 24;
constexpr std::size_t kVersionSize = kVersionTextSize + 8 + kNameSize;
constexpr std::size_t kRcTaskRecordSize = 8;
constexpr std::size_t kOwnerStateSize = 16 + kMaxRcTasks * kRcTaskRecordSize;
constexpr std::size_t kDiagRecordSize = 40;
static_assert(kStatusSize <= kMaxPayload && kListHeadSize + kMaxSlaves * kSlaveRecordSize <= kMaxPayload &&
                  kListHeadSize + kMaxTasks * kTaskRecordSize + kListHeadSize + kMaxDropCounters * 8 <= kMaxPayload &&
                  kDiagHeadSize + kMaxSlaves * kDiagRecordSize <= kMaxPayload,
              "every payload fits");

constexpr double kPi = 3.14159265358979323846;

// Sequential little-endian writer over a buffer whose size the caller checked.
class Writer {
 public:
  explicit Writer(std::uint8_t* p) noexcept : p_(p) {}
  void u8(std::uint8_t v) noexcept { p_[n_++] = v; }
  void zeros(std::size_t count) noexcept {
    for (std::size_t i = 0; i < count; ++i) p_[n_++] = 0;
  }
  void u16(std::uint16_t v) noexcept {
    store_le16(p_ + n_, v);
    n_ += 2;
  }
  void u32(std::uint32_t v) noexcept {
    store_le32(p_ + n_, v);
    n_ += 4;
  }
  void u64(std::uint64_t v) noexcept {
    store_le64(p_ + n_, v);
    n_ += 8;
  }
  void f64(double v) noexcept {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    u64(bits);
  }
  template <std::size_t N>
  void text(const std::array<char, N>& t) noexcept {
    for (std::size_t i = 0; i < N; ++i) p_[n_++] = i + 1 < N ? static_cast<std::uint8_t>(t[i]) : 0;
  }
  std::size_t size() const noexcept { return n_; }

 private:
  std::uint8_t* p_;
  std::size_t n_{0};
};

// Sequential reader; the caller checked the total length first, so reads stay in bounds.
class Reader {
 public:
  explicit Reader(ConstByteSpan bytes) noexcept : b_(bytes) {}
  std::uint8_t u8() noexcept { return b_[n_++]; }
  bool zeros(std::size_t count) noexcept {
    bool all = true;
    for (std::size_t i = 0; i < count; ++i) all = all && b_[n_++] == 0;
    return all;
  }
  std::uint16_t u16() noexcept {
    const std::uint16_t v = load_le16(b_.data() + n_);
    n_ += 2;
    return v;
  }
  std::uint32_t u32() noexcept {
    const std::uint32_t v = load_le32(b_.data() + n_);
    n_ += 4;
    return v;
  }
  std::uint64_t u64() noexcept {
    const std::uint64_t v = load_le64(b_.data() + n_);
    n_ += 8;
    return v;
  }
  double f64() noexcept {
    const std::uint64_t bits = u64();
    double v = 0.0;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  // A NUL-padded text field: false when its last byte is not NUL.
  template <std::size_t N>
  bool text(std::array<char, N>& out) noexcept {
    for (std::size_t i = 0; i < N; ++i) out[i] = static_cast<char>(b_[n_++]);
    return out[N - 1] == '\0';
  }

 private:
  ConstByteSpan b_;
  std::size_t n_{0};
};

Error malformed(const char* what, std::size_t d0 = 0, std::size_t d1 = 0) noexcept {
  return make_error(Errc::malformed, what, static_cast<std::uint32_t>(d0), static_cast<std::uint32_t>(d1));
}
Error out_of_range(const char* what) noexcept { return make_error(Errc::out_of_range, what); }

bool within(double v, double lo, double hi) noexcept { return std::isfinite(v) && v >= lo && v <= hi; }

Status check_length(ConstByteSpan payload, std::size_t expected) noexcept {
  if (payload.size() != expected) return malformed("payload length differs from its type's", payload.size(), expected);
  return Status::success();
}

Status check_joints(JointMask joints) noexcept {
  if (joints == 0) return out_of_range("no joint selected");
  if ((joints & ~kAllJoints) != 0) return out_of_range("joint mask names a joint the robot does not have");
  return Status::success();
}

bool valid_mode(std::uint8_t mode) noexcept {
  return mode == static_cast<std::uint8_t>(ControlMode::cyclic_position) ||
         mode == static_cast<std::uint8_t>(ControlMode::cyclic_velocity) ||
         mode == static_cast<std::uint8_t>(ControlMode::cyclic_torque);
}

Status decode_joints(const Header& h, ConstByteSpan payload, Message& m) noexcept {
  const bool with_mode = h.type == MessageType::select_mode;
  RESCUE_TRY(check_length(payload, with_mode ? kSelectModeSize : kJointsSize));
  Reader r(payload);
  m.joints.joints = r.u32();
  if (with_mode) {
    const std::uint8_t mode = r.u8();
    if (!r.zeros(3)) return malformed("reserved bytes not zero");
    if (!valid_mode(mode)) return out_of_range("mode must be CSP (8), CSV (9) or CST (10)");
    m.joints.mode = static_cast<ControlMode>(mode);
  }
  return check_joints(m.joints.joints);
}

Status decode_move(ConstByteSpan payload, Message& m) noexcept {
  RESCUE_TRY(check_length(payload, kMoveSize));
  Reader r(payload);
  m.move.task = r.u8();
  const std::uint8_t effector = r.u8();
  if (!r.zeros(6)) return malformed("reserved bytes not zero");
  for (double& v : m.move.position_m) v = r.f64();
  for (double& v : m.move.rpy_rad) v = r.f64();
  if (m.move.task >= kMaxRcTasks) return out_of_range("RC task index");
  if (effector > 1) return out_of_range("effector");
  m.move.effector = static_cast<Effector>(effector);
  for (const double v : m.move.position_m) {
    if (!within(v, -kMaxReachM, kMaxReachM)) return out_of_range("position beyond the robot's reach");
  }
  for (const double v : m.move.rpy_rad) {
    if (!within(v, -kPi, kPi)) return out_of_range("orientation angle outside [-pi, pi]");
  }
  return Status::success();
}

Status decode_hand(ConstByteSpan payload, Message& m) noexcept {
  RESCUE_TRY(check_length(payload, kHandSize));
  Reader r(payload);
  m.hand.task = r.u8();
  const std::uint8_t hand = r.u8();
  const std::uint8_t action = r.u8();
  if (!r.zeros(1)) return malformed("reserved bytes not zero");
  if (m.hand.task >= kMaxRcTasks) return out_of_range("RC task index");
  if (hand > 1) return out_of_range("hand");
  if (action > 1) return out_of_range("hand action");
  m.hand.hand = static_cast<Effector>(hand);
  m.hand.action = static_cast<HandAction>(action);
  return Status::success();
}

Status decode_owner(ConstByteSpan payload, Message& m) noexcept {
  RESCUE_TRY(check_length(payload, kOwnerSize));
  Reader r(payload);
  m.owner.task = r.u8();
  if (!r.zeros(3)) return malformed("reserved bytes not zero");
  if (m.owner.task >= kMaxRcTasks) return out_of_range("RC task index");
  return Status::success();
}

Status decode_imu(ConstByteSpan payload, Message& m) noexcept {
  RESCUE_TRY(check_length(payload, kImuSize));
  Reader r(payload);
  m.imu.time_unix_ns = r.u64();
  for (double& v : m.imu.orientation_wxyz) v = r.f64();
  for (double& v : m.imu.angular_velocity_rad_s) v = r.f64();
  for (double& v : m.imu.linear_acceleration_m_s2) v = r.f64();
  double norm2 = 0.0;
  for (const double v : m.imu.orientation_wxyz) {
    if (!within(v, -1.0 - kQuaternionNormTolerance, 1.0 + kQuaternionNormTolerance)) {
      return out_of_range("quaternion component");
    }
    norm2 += v * v;
  }
  if (std::fabs(std::sqrt(norm2) - 1.0) > kQuaternionNormTolerance) return out_of_range("quaternion not of unit norm");
  for (const double v : m.imu.angular_velocity_rad_s) {
    if (!within(v, -kMaxAngularVelocityRadS, kMaxAngularVelocityRadS)) return out_of_range("angular velocity");
  }
  for (const double v : m.imu.linear_acceleration_m_s2) {
    if (!within(v, -kMaxAccelerationMs2, kMaxAccelerationMs2)) return out_of_range("linear acceleration");
  }
  return Status::success();
}

Status decode_gps(ConstByteSpan payload, Message& m) noexcept {
  RESCUE_TRY(check_length(payload, kGpsSize));
  Reader r(payload);
  m.gps.time_unix_ns = r.u64();
  m.gps.latitude_deg = r.f64();
  m.gps.longitude_deg = r.f64();
  m.gps.altitude_m = r.f64();
  m.gps.horizontal_accuracy_m = r.f64();
  m.gps.vertical_accuracy_m = r.f64();
  const std::uint8_t fix = r.u8();
  m.gps.satellites = r.u8();
  if (!r.zeros(6)) return malformed("reserved bytes not zero");
  if (!within(m.gps.latitude_deg, -90.0, 90.0)) return out_of_range("latitude");
  if (!within(m.gps.longitude_deg, -180.0, 180.0)) return out_of_range("longitude");
  if (!within(m.gps.altitude_m, -1000.0, 10000.0)) return out_of_range("altitude");
  if (!within(m.gps.horizontal_accuracy_m, 0.0, 10000.0)) return out_of_range("horizontal accuracy");
  if (!within(m.gps.vertical_accuracy_m, 0.0, 10000.0)) return out_of_range("vertical accuracy");
  if (fix > static_cast<std::uint8_t>(GpsFix::rtk)) return out_of_range("fix type");
  m.gps.fix = static_cast<GpsFix>(fix);
  return Status::success();
}

Status decode_reply(ConstByteSpan payload, Message& m) noexcept {
  RESCUE_TRY(check_length(payload, kReplySize));
  Reader r(payload);
  m.reply.request_sequence = r.u64();
  const std::uint8_t type = r.u8();
  const std::uint8_t outcome = r.u8();
  const std::uint8_t reason = r.u8();
  if (!r.zeros(1)) return malformed("reserved bytes not zero");
  m.reply.refused_joints = r.u32();
  if (!r.text(m.reply.text)) return malformed("reply text not NUL-terminated");
  for (std::size_t j = 0; j < kJointCount; ++j) {
    JointRefusalRecord& jr = m.reply.joint_refusals[j];
    const std::uint8_t why = r.u8();
    jr.state = r.u8();
    jr.input = r.u8();
    if (!r.zeros(1)) return malformed("reserved bytes not zero");
    if (why > kJointRefusalLast) return out_of_range("joint refusal");
    if (jr.state >= fsm::kJointStateCount || jr.input >= fsm::kJointInputCount) return out_of_range("joint state or input");
    jr.why = static_cast<JointRefusal>(why);
    if (jr.why != JointRefusal::none && (m.reply.refused_joints & joint_bit(j)) == 0) {
      return out_of_range("joint refusal of a joint not refused");
    }
  }
  if (!is_known(type)) return out_of_range("request type");
  if (outcome > 1) return out_of_range("outcome");
  if (reason > static_cast<std::uint8_t>(RefusalReason::sender_table_full)) return out_of_range("refusal reason");
  if ((m.reply.refused_joints & ~kAllJoints) != 0) return out_of_range("refused joint mask");
  m.reply.request_type = static_cast<MessageType>(type);
  m.reply.outcome = static_cast<Outcome>(outcome);
  m.reply.reason = static_cast<RefusalReason>(reason);
  return Status::success();
}

Status decode_status(ConstByteSpan payload, Message& m) noexcept {
  RESCUE_TRY(check_length(payload, kStatusSize));
  Reader r(payload);
  m.status.cycle = r.u64();
  const std::uint8_t count = r.u8();
  if (!r.zeros(7)) return malformed("reserved bytes not zero");
  if (count != kJointCount) return out_of_range("joint count");
  for (JointStatusRecord& j : m.status.joints) {
    j.state = r.u8();
    j.mode = static_cast<std::int8_t>(r.u8());
    j.flags = r.u8();
    j.fault = r.u8();
    j.owner = r.u8();
    if (!r.zeros(3)) return malformed("reserved bytes not zero");
    j.position_rad = r.f64();
    j.velocity_rad_s = r.f64();
    j.torque_nm = r.f64();
    if (j.state > 4 || (j.flags & ~kJointFlagsMask) != 0 || j.fault > 9) return out_of_range("joint status field");
    if (j.owner != kNoOwner && j.owner >= kMaxRcTasks) return out_of_range("owner");
  }
  return Status::success();
}

Status decode_slaves(ConstByteSpan payload, Message& m) noexcept {
  if (payload.size() < kListHeadSize) return malformed("payload shorter than its list header", payload.size());
  Reader r(payload);
  m.slaves.count = r.u8();
  if (!r.zeros(7)) return malformed("reserved bytes not zero");
  if (m.slaves.count > kMaxSlaves) return out_of_range("slave count");
  RESCUE_TRY(check_length(payload, kListHeadSize + m.slaves.count * kSlaveRecordSize));
  for (std::size_t i = 0; i < m.slaves.count; ++i) {
    SlaveRecord& s = m.slaves.slaves[i];
    s.position = r.u16();
    s.station = r.u16();
    s.al_state = r.u8();
    s.flags = r.u8();
    if (!r.zeros(2)) return malformed("reserved bytes not zero");
    if (!r.text(s.name)) return malformed("slave name not NUL-terminated");
    if ((s.flags & ~kSlaveFlagsMask) != 0) return out_of_range("slave flags");
  }
  return Status::success();
}

Status decode_master(ConstByteSpan payload, Message& m) noexcept {
  RESCUE_TRY(check_length(payload, kMasterSize));
  Reader r(payload);
  m.master.state = r.u8();
  if (!r.zeros(7)) return malformed("reserved bytes not zero");
  m.master.cycles = r.u64();
  m.master.frames_sent = r.u64();
  m.master.frames_lost = r.u64();
  m.master.late_periods = r.u64();
  m.master.dc_deviation_ns = static_cast<std::int64_t>(r.u64());
  m.master.dc_max_deviation_ns = static_cast<std::int64_t>(r.u64());
  m.master.datagrams_accepted = r.u64();
  for (std::uint64_t& v : m.master.rejected) v = r.u64();
  if (m.master.state > 4) return out_of_range("master state");
  return Status::success();
}

Status decode_tasks(ConstByteSpan payload, Message& m) noexcept {
  if (payload.size() < kListHeadSize) return malformed("payload shorter than its list header", payload.size());
  Reader r(payload);
  m.tasks.count = r.u8();
  if (!r.zeros(7)) return malformed("reserved bytes not zero");
  if (m.tasks.count > kMaxTasks) return out_of_range("task count");
  const std::size_t drops_at = kListHeadSize + m.tasks.count * kTaskRecordSize;
  if (payload.size() < drops_at + kListHeadSize) return malformed("payload shorter than its drop counters' header", payload.size());
  const std::uint8_t drop_count = payload[drops_at];
  if (drop_count > kMaxDropCounters) return out_of_range("drop counter count");
  RESCUE_TRY(check_length(payload, drops_at + kListHeadSize + drop_count * 8U));
  for (std::size_t i = 0; i < m.tasks.count; ++i) {
    TaskRecord& t = m.tasks.tasks[i];
    if (!r.text(t.name)) return malformed("task name not NUL-terminated");
    t.pid = static_cast<std::int32_t>(r.u32());
    t.cpu = static_cast<std::int16_t>(r.u16());
    t.priority = static_cast<std::int16_t>(r.u16());
    t.policy = static_cast<std::int8_t>(r.u8());
    if (!r.zeros(1)) return malformed("reserved bytes not zero");
    t.table_cpu = static_cast<std::int16_t>(r.u16());
    t.table_priority = static_cast<std::int16_t>(r.u16());
    if (!r.zeros(2)) return malformed("reserved bytes not zero");
    t.periods = r.u64();
    t.missed = r.u64();
    t.max_execution_ns = r.u64();
    for (TimingFigures* f : {&t.execution, &t.latency}) {
      f->min = r.u32();
      f->mean = r.u32();
      f->stddev = r.u32();
      f->max = r.u32();
      f->p99 = r.u32();
      f->p999 = r.u32();
      f->p9999 = r.u32();
    }
  }
  m.tasks.drop_count = r.u8();
  if (!r.zeros(7)) return malformed("reserved bytes not zero");
  for (std::size_t i = 0; i < m.tasks.drop_count; ++i) m.tasks.dropped[i] = r.u64();
  return Status::success();
}

Status decode_version(ConstByteSpan payload, Message& m) noexcept {
  RESCUE_TRY(check_length(payload, kVersionSize));
  Reader r(payload);
  if (!r.text(m.version.program)) return malformed("program version not NUL-terminated");
  m.version.layout_version = r.u32();
  m.version.layout_hash = r.u32();
  if (!r.text(m.version.build_type)) return malformed("build type not NUL-terminated");
  return Status::success();
}

Status decode_owner_state(ConstByteSpan payload, Message& m) noexcept {
  RESCUE_TRY(check_length(payload, kOwnerStateSize));
  Reader r(payload);
  m.owner_state.owner = r.u8();
  if (!r.zeros(7)) return malformed("reserved bytes not zero");
  m.owner_state.generation = r.u64();
  if (m.owner_state.owner >= kMaxRcTasks && m.owner_state.owner != kNoOwner) return out_of_range("owner task");
  for (RcTaskRecord& t : m.owner_state.tasks) {
    t.present = r.u8();
    t.alive = r.u8();
    t.phase = r.u8();
    t.mode = r.u8();
    t.heartbeat_age_ms = r.u32();
    if (t.present > 1 || t.alive > 1) return out_of_range("RC task flags");
  }
  return Status::success();
}

Status decode_diag(ConstByteSpan payload, Message& m) noexcept {
  if (payload.size() < kDiagHeadSize) return malformed("payload shorter than its diag header", payload.size());
  Reader r(payload);
  m.diag.count = r.u8();
  if (!r.zeros(7)) return malformed("reserved bytes not zero");
  if (m.diag.count > kMaxSlaves) return out_of_range("slave count");
  RESCUE_TRY(check_length(payload, kDiagHeadSize + m.diag.count * kDiagRecordSize));
  m.diag.cycle = r.u64();
  m.diag.sweeps = r.u64();
  for (std::size_t i = 0; i < m.diag.count; ++i) {
    DiagSlaveRecord& d = m.diag.slaves[i];
    for (DiagPortRecord& p : d.ports) {
      p.invalid_frames = r.u16();
      p.rx_errors = r.u16();
      p.forwarded_errors = r.u16();
      p.lost_links = r.u16();
    }
    d.processing_unit_errors = r.u16();
    d.pdi_errors = r.u16();
    d.reads = r.u16();
    d.warned = r.u8();
    d.warned_before = r.u8();
    if (((d.warned | d.warned_before) & ~kDiagWarnedMask) != 0) return out_of_range("warned ports");
  }
  return Status::success();
}

}  // namespace

const char* to_string(MessageType type) noexcept {
  switch (type) {
    case MessageType::get_status: return "get_status";
    case MessageType::get_slaves: return "get_slaves";
    case MessageType::get_master: return "get_master";
    case MessageType::get_tasks: return "get_tasks";
    case MessageType::get_diag: return "get_diag";
    case MessageType::get_epoch: return "get_epoch";
    case MessageType::get_version: return "get_version";
    case MessageType::get_owner: return "get_owner";
    case MessageType::initialize: return "initialize";
    case MessageType::enable: return "enable";
    case MessageType::disable: return "disable";
    case MessageType::hold: return "hold";
    case MessageType::select_mode: return "select_mode";
    case MessageType::clear_joints: return "clear_joints";
    case MessageType::clear_moved: return "clear_moved";
    case MessageType::move_effector: return "move_effector";
    case MessageType::hand: return "hand";
    case MessageType::take_owner: return "take_owner";
    case MessageType::imu: return "imu";
    case MessageType::gps: return "gps";
    case MessageType::reply: return "reply";
    case MessageType::status: return "status";
    case MessageType::slaves: return "slaves";
    case MessageType::master: return "master";
    case MessageType::tasks: return "tasks";
    case MessageType::diag: return "diag";
    case MessageType::epoch: return "epoch";
    case MessageType::version: return "version";
    case MessageType::owner_state: return "owner_state";
  }
  return "?";
}

bool is_known(std::uint8_t type) noexcept {
  switch (static_cast<MessageType>(type)) {
    case MessageType::get_status:
    case MessageType::get_slaves:
    case MessageType::get_master:
    case MessageType::get_tasks:
    case MessageType::get_diag:
    case MessageType::get_epoch:
    case MessageType::get_version:
    case MessageType::get_owner:
    case MessageType::initialize:
    case MessageType::enable:
    case MessageType::disable:
    case MessageType::hold:
    case MessageType::select_mode:
    case MessageType::clear_joints:
    case MessageType::clear_moved:
    case MessageType::move_effector:
    case MessageType::hand:
    case MessageType::take_owner:
    case MessageType::imu:
    case MessageType::gps:
    case MessageType::reply:
    case MessageType::status:
    case MessageType::slaves:
    case MessageType::master:
    case MessageType::tasks:
    case MessageType::diag:
    case MessageType::epoch:
    case MessageType::version:
    case MessageType::owner_state:
      return true;
  }
  return false;
}

bool is_query(MessageType type) noexcept {
  const auto t = static_cast<std::uint8_t>(type);
  return (t >= 0x01 && t <= 0x05) || t == 0x07 || t == 0x08;  // get_epoch (0x06) is answered before any query
}
bool is_control_request(MessageType type) noexcept {
  const auto t = static_cast<std::uint8_t>(type);
  return is_known(t) && t < 0x40;
}
bool is_sensor_record(MessageType type) noexcept { return type == MessageType::imu || type == MessageType::gps; }

const char* to_string(Rejection reason) noexcept {
  switch (reason) {
    case Rejection::malformed: return "malformed";
    case Rejection::oversized: return "oversized";
    case Rejection::unauthenticated: return "unauthenticated";
    case Rejection::replayed: return "replayed";
    case Rejection::out_of_range: return "out_of_range";
    case Rejection::unknown_type: return "unknown_type";
    case Rejection::wrong_robot: return "wrong_robot";
    case Rejection::sender_table_full: return "sender_table_full";
  }
  return "?";
}

const char* to_string(RefusalReason reason) noexcept {
  switch (reason) {
    case RefusalReason::none: return "none";
    case RefusalReason::state_machine: return "state machine refusal";
    case RefusalReason::unreachable_joint: return "unreachable joint";
    case RefusalReason::not_owner: return "not owner";
    case RefusalReason::no_rc_task: return "no RC task running";
    case RefusalReason::busy: return "busy";
    case RefusalReason::bad_request: return "bad request";
    case RefusalReason::clear_refused: return "clear refused";
    case RefusalReason::sender_table_full: return "sender table full";
  }
  return "?";
}

const char* to_string(JointRefusal refusal) noexcept {
  switch (refusal) {
    case JointRefusal::none: return "none";
    case JointRefusal::state_machine: return "state machine refusal";
    case JointRefusal::unreachable: return "unreachable joint";
    case JointRefusal::bad_mode: return "select_mode needs CSP, CSV or CST";
    case JointRefusal::not_lost: return "not recorded lost: nothing to clear";
    case JointRefusal::still_unreachable: return "still unreachable: repair it first";
    case JointRefusal::moved: return "position differs from the held position: check it, then clear --moved";
    case JointRefusal::file_not_written: return "the error-joints file could not be written";
  }
  return "?";
}

RefusalReason reason_of(JointRefusal refusal) noexcept {
  switch (refusal) {
    case JointRefusal::none: return RefusalReason::none;
    case JointRefusal::state_machine: return RefusalReason::state_machine;
    case JointRefusal::unreachable: return RefusalReason::unreachable_joint;
    case JointRefusal::bad_mode: return RefusalReason::bad_request;
    case JointRefusal::not_lost:
    case JointRefusal::still_unreachable:
    case JointRefusal::moved:
    case JointRefusal::file_not_written: return RefusalReason::clear_refused;
  }
  return RefusalReason::busy;
}

Rejection rejection_of(const Error& error) noexcept {
  switch (error.code) {
    case Errc::capacity_exceeded: return Rejection::oversized;
    case Errc::out_of_range: return Rejection::out_of_range;
    case Errc::unsupported: return Rejection::unknown_type;
    case Errc::checksum: return Rejection::unauthenticated;
    case Errc::refused: return Rejection::replayed;
    default: return Rejection::malformed;
  }
}

Result<FrameView> parse_frame(ConstByteSpan datagram) noexcept {
  if (datagram.size() > kMaxDatagram) {
    return make_error(Errc::capacity_exceeded, "datagram longer than the protocol's maximum",
                      static_cast<std::uint32_t>(datagram.size()), static_cast<std::uint32_t>(kMaxDatagram));
  }
  if (datagram.size() < kHeaderSize + kTagSize) return malformed("datagram shorter than header and tag", datagram.size());
  const std::uint8_t* p = datagram.data();
  if (std::memcmp(p, kMagic.data(), kMagic.size()) != 0) return malformed("bad magic");
  FrameView f;
  f.header.version = p[4];
  if (f.header.version != kVersion) return malformed("unsupported protocol version", f.header.version, kVersion);
  f.header.type = static_cast<MessageType>(p[5]);
  f.header.flags = p[6];
  if (f.header.flags != 0 || p[7] != 0) return malformed("reserved header bytes not zero");
  for (std::size_t i = 34; i < kHeaderSize; ++i) {
    if (p[i] != 0) return malformed("reserved header bytes not zero");
  }
  f.header.sender = load_le32(p + 8);
  f.header.robot = load_le32(p + 12);
  f.header.epoch = load_le64(p + 16);
  f.header.sequence = load_le64(p + 24);
  f.header.payload_length = load_le16(p + 32);
  // Only get_epoch may leave the robot and the epoch open; the robot's epoch answer never does.
  const bool asks_epoch = f.header.type == MessageType::get_epoch;
  if (asks_epoch && f.header.epoch != 0) return malformed("get_epoch with an epoch");
  if (!asks_epoch && (f.header.epoch == 0 || f.header.robot == kAnyRobot)) return malformed("no robot id or no epoch");
  if (f.header.payload_length > kMaxPayload) {
    return make_error(Errc::capacity_exceeded, "payload length above the protocol's maximum", f.header.payload_length,
                      static_cast<std::uint32_t>(kMaxPayload));
  }
  if (datagram.size() != kHeaderSize + f.header.payload_length + kTagSize) {
    return malformed("datagram length differs from header + payload + tag", datagram.size(), f.header.payload_length);
  }
  f.signed_bytes = datagram.subspan(0, kHeaderSize + f.header.payload_length);
  f.payload = datagram.subspan(kHeaderSize, f.header.payload_length);
  f.tag = datagram.subspan(kHeaderSize + f.header.payload_length, kTagSize);
  return f;
}

Result<Message> decode_payload(const Header& header, ConstByteSpan payload) noexcept {
  Message m;
  m.header = header;
  Status s;
  if (!is_known(static_cast<std::uint8_t>(header.type))) {
    return make_error(Errc::unsupported, "unknown message type", static_cast<std::uint8_t>(header.type));
  }
  switch (header.type) {
    case MessageType::get_status:
    case MessageType::get_slaves:
    case MessageType::get_master:
    case MessageType::get_tasks:
    case MessageType::get_diag:
    case MessageType::get_epoch:
    case MessageType::get_version:
    case MessageType::get_owner:
      s = check_length(payload, 0);
      break;
    case MessageType::initialize:
    case MessageType::enable:
    case MessageType::disable:
    case MessageType::hold:
    case MessageType::select_mode:
    case MessageType::clear_joints:
    case MessageType::clear_moved:
      s = decode_joints(header, payload, m);
      break;
    case MessageType::move_effector: s = decode_move(payload, m); break;
    case MessageType::hand: s = decode_hand(payload, m); break;
    case MessageType::take_owner: s = decode_owner(payload, m); break;
    case MessageType::imu: s = decode_imu(payload, m); break;
    case MessageType::gps: s = decode_gps(payload, m); break;
    case MessageType::reply: s = decode_reply(payload, m); break;
    case MessageType::status: s = decode_status(payload, m); break;
    case MessageType::slaves: s = decode_slaves(payload, m); break;
    case MessageType::master: s = decode_master(payload, m); break;
    case MessageType::tasks: s = decode_tasks(payload, m); break;
    case MessageType::diag: s = decode_diag(payload, m); break;
    case MessageType::epoch:
      s = check_length(payload, kEpochSize);
      if (s.ok()) m.epoch.request_sequence = load_le64(payload.data());
      break;
    case MessageType::version: s = decode_version(payload, m); break;
    case MessageType::owner_state: s = decode_owner_state(payload, m); break;
  }
  if (!s.ok()) return s.error();
  return m;
}

void encode_header(const Header& h, std::uint8_t* out) noexcept {
  Writer w(out);
  for (const std::uint8_t b : kMagic) w.u8(b);
  w.u8(h.version);
  w.u8(static_cast<std::uint8_t>(h.type));
  w.u8(h.flags);
  w.u8(0);
  w.u32(h.sender);
  w.u32(h.robot);
  w.u64(h.epoch);
  w.u64(h.sequence);
  w.u16(h.payload_length);
  w.zeros(6);
}

Result<std::size_t> encode_payload(const Message& m, ByteSpan out) noexcept {
  std::array<std::uint8_t, kMaxPayload> buf{};
  Writer w(buf.data());
  switch (m.header.type) {
    case MessageType::get_status:
    case MessageType::get_slaves:
    case MessageType::get_master:
    case MessageType::get_tasks:
    case MessageType::get_diag:
    case MessageType::get_epoch:
      break;
    case MessageType::epoch:
      w.u64(m.epoch.request_sequence);
    case MessageType::get_version:
    case MessageType::get_owner:
      break;
    case MessageType::version:
      w.text(m.version.program);
      w.u32(m.version.layout_version);
      w.u32(m.version.layout_hash);
      w.text(m.version.build_type);
      break;
    case MessageType::owner_state:
      w.u8(m.owner_state.owner);
      w.zeros(7);
      w.u64(m.owner_state.generation);
      for (const RcTaskRecord& t : m.owner_state.tasks) {
        w.u8(t.present);
        w.u8(t.alive);
        w.u8(t.phase);
        w.u8(t.mode);
        w.u32(t.heartbeat_age_ms);
      }
      break;
    case MessageType::initialize:
    case MessageType::enable:
    case MessageType::disable:
    case MessageType::hold:
    case MessageType::clear_joints:
    case MessageType::clear_moved:
      w.u32(m.joints.joints);
      break;
    case MessageType::select_mode:
      w.u32(m.joints.joints);
      w.u8(static_cast<std::uint8_t>(m.joints.mode));
      w.zeros(3);
      break;
    case MessageType::move_effector:
      w.u8(m.move.task);
      w.u8(static_cast<std::uint8_t>(m.move.effector));
      w.zeros(6);
      for (const double v : m.move.position_m) w.f64(v);
      for (const double v : m.move.rpy_rad) w.f64(v);
      break;
    case MessageType::hand:
      w.u8(m.hand.task);
      w.u8(static_cast<std::uint8_t>(m.hand.hand));
      w.u8(static_cast<std::uint8_t>(m.hand.action));
      w.zeros(1);
      break;
    case MessageType::take_owner:
      w.u8(m.owner.task);
      w.zeros(3);
      break;
    case MessageType::imu:
      w.u64(m.imu.time_unix_ns);
      for (const double v : m.imu.orientation_wxyz) w.f64(v);
      for (const double v : m.imu.angular_velocity_rad_s) w.f64(v);
      for (const double v : m.imu.linear_acceleration_m_s2) w.f64(v);
      break;
    case MessageType::gps:
      w.u64(m.gps.time_unix_ns);
      w.f64(m.gps.latitude_deg);
      w.f64(m.gps.longitude_deg);
      w.f64(m.gps.altitude_m);
      w.f64(m.gps.horizontal_accuracy_m);
      w.f64(m.gps.vertical_accuracy_m);
      w.u8(static_cast<std::uint8_t>(m.gps.fix));
      w.u8(m.gps.satellites);
      w.zeros(6);
      break;
    case MessageType::reply:
      w.u64(m.reply.request_sequence);
      w.u8(static_cast<std::uint8_t>(m.reply.request_type));
      w.u8(static_cast<std::uint8_t>(m.reply.outcome));
      w.u8(static_cast<std::uint8_t>(m.reply.reason));
      w.zeros(1);
      w.u32(m.reply.refused_joints);
      w.text(m.reply.text);
      for (const JointRefusalRecord& jr : m.reply.joint_refusals) {
        w.u8(static_cast<std::uint8_t>(jr.why));
        w.u8(jr.state);
        w.u8(jr.input);
        w.u8(0);
      }
      break;
    case MessageType::status:
      w.u64(m.status.cycle);
      w.u8(static_cast<std::uint8_t>(kJointCount));
      w.zeros(7);
      for (const JointStatusRecord& j : m.status.joints) {
        w.u8(j.state);
        w.u8(static_cast<std::uint8_t>(j.mode));
        w.u8(j.flags);
        w.u8(j.fault);
        w.u8(j.owner);
        w.zeros(3);
        w.f64(j.position_rad);
        w.f64(j.velocity_rad_s);
        w.f64(j.torque_nm);
      }
      break;
    case MessageType::slaves: {
      const std::size_t count = m.slaves.count <= kMaxSlaves ? m.slaves.count : kMaxSlaves;
      w.u8(static_cast<std::uint8_t>(count));
      w.zeros(7);
      for (std::size_t i = 0; i < count; ++i) {
        const SlaveRecord& s = m.slaves.slaves[i];
        w.u16(s.position);
        w.u16(s.station);
        w.u8(s.al_state);
        w.u8(s.flags);
        w.zeros(2);
        w.text(s.name);
      }
      break;
    }
    case MessageType::master:
      w.u8(m.master.state);
      w.zeros(7);
      w.u64(m.master.cycles);
      w.u64(m.master.frames_sent);
      w.u64(m.master.frames_lost);
      w.u64(m.master.late_periods);
      w.u64(static_cast<std::uint64_t>(m.master.dc_deviation_ns));
      w.u64(static_cast<std::uint64_t>(m.master.dc_max_deviation_ns));
      w.u64(m.master.datagrams_accepted);
      for (const std::uint64_t v : m.master.rejected) w.u64(v);
      break;
    case MessageType::tasks: {
      const std::size_t count = m.tasks.count <= kMaxTasks ? m.tasks.count : kMaxTasks;
      w.u8(static_cast<std::uint8_t>(count));
      w.zeros(7);
      for (std::size_t i = 0; i < count; ++i) {
        const TaskRecord& t = m.tasks.tasks[i];
        w.text(t.name);
        w.u32(static_cast<std::uint32_t>(t.pid));
        w.u16(static_cast<std::uint16_t>(t.cpu));
        w.u16(static_cast<std::uint16_t>(t.priority));
        w.u8(static_cast<std::uint8_t>(t.policy));
        w.zeros(1);
        w.u16(static_cast<std::uint16_t>(t.table_cpu));
        w.u16(static_cast<std::uint16_t>(t.table_priority));
        w.zeros(2);
        w.u64(t.periods);
        w.u64(t.missed);
        w.u64(t.max_execution_ns);
        for (const TimingFigures* f : {&t.execution, &t.latency}) {
          w.u32(f->min);
          w.u32(f->mean);
          w.u32(f->stddev);
          w.u32(f->max);
          w.u32(f->p99);
          w.u32(f->p999);
          w.u32(f->p9999);
        }
      }
      const std::size_t drops = m.tasks.drop_count <= kMaxDropCounters ? m.tasks.drop_count : kMaxDropCounters;
      w.u8(static_cast<std::uint8_t>(drops));
      w.zeros(7);
      for (std::size_t i = 0; i < drops; ++i) w.u64(m.tasks.dropped[i]);
      break;
    }
    case MessageType::diag: {
      const std::size_t count = m.diag.count <= kMaxSlaves ? m.diag.count : kMaxSlaves;
      w.u8(static_cast<std::uint8_t>(count));
      w.zeros(7);
      w.u64(m.diag.cycle);
      w.u64(m.diag.sweeps);
      for (std::size_t i = 0; i < count; ++i) {
        const DiagSlaveRecord& d = m.diag.slaves[i];
        for (const DiagPortRecord& p : d.ports) {
          w.u16(p.invalid_frames);
          w.u16(p.rx_errors);
          w.u16(p.forwarded_errors);
          w.u16(p.lost_links);
        }
        w.u16(d.processing_unit_errors);
        w.u16(d.pdi_errors);
        w.u16(d.reads);
        w.u8(d.warned);
        w.u8(d.warned_before);
      }
      break;
    }
    default:
      return make_error(Errc::unsupported, "unknown message type", static_cast<std::uint8_t>(m.header.type));
  }
  if (w.size() > out.size()) return make_error(Errc::capacity_exceeded, "payload buffer too small");
  std::memcpy(out.data(), buf.data(), w.size());
  return w.size();
}

}  // namespace rescue::app::protocol
