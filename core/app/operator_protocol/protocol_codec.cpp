#include "core/app/operator_protocol/protocol_codec.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <type_traits>

#include "core/base/le_stream.hpp"
#include "core/robot/joint_fault.hpp"
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
constexpr std::size_t kSlaveRecordSize = 40;
constexpr std::size_t kMasterSize = 64 + kRejectionCount * 8;
constexpr std::size_t kEpochSize = 8;
constexpr std::size_t kTimingFiguresSize = 28;  // 7 x u32 ns
constexpr std::size_t kTaskRecordSize = 72 + 2 * kTimingFiguresSize;  // + policy, table CPU and priority, tid, restarts, uptime
constexpr std::size_t kDiagHeadSize = 24;
constexpr std::size_t kVersionSize = kVersionTextSize + 8 + kNameSize;
constexpr std::size_t kRcTaskRecordSize = 8;
constexpr std::size_t kOwnerStateSize = 16 + kMaxRcTasks * kRcTaskRecordSize;
constexpr std::size_t kDiagRecordSize = 40;
constexpr std::size_t kSdoUploadSize = 8;
constexpr std::size_t kSdoDownloadSize = 8 + kSdoDataSize;
constexpr std::size_t kSdoResultSize = 32 + kSdoTextSize + kSdoDataSize;
constexpr std::size_t kSlaveInfoRecordSize = 28;
constexpr std::size_t kGraphRecordSize = 12;
constexpr std::size_t kGraphRingSize = 12;
constexpr std::size_t kDiagResetSize = 4;
constexpr std::size_t kSiiRequestSize = 4;
constexpr std::size_t kSiiSize = 8 + kSiiChunkBytes;
constexpr std::size_t kRegReadSize = 8;
constexpr std::size_t kRegResultSize = 24 + kRegDataSize;
constexpr std::size_t kSdoInfoSize = 12;
constexpr std::size_t kSdoInfoResultSize = 44 + kSdoTextSize + kSdoDataSize;
constexpr std::size_t kStatesSize = 8;
constexpr std::size_t kStatesRecordSize = 6;
constexpr std::size_t kStatesResultSize = 24 + kMaxSlaves * kStatesRecordSize;
constexpr std::size_t kRescanSize = 4;
constexpr std::size_t kRescanDeviceSize = 20;
constexpr std::size_t kRescanDifferenceSize = 4;
constexpr std::size_t kRescanResultSize =
    24 + kRescanDevices * kRescanDeviceSize + kRescanDifferences * kRescanDifferenceSize;
static_assert(kStatusSize <= kMaxPayload && kListHeadSize + kMaxSlaves * kSlaveRecordSize <= kMaxPayload &&
                  kListHeadSize + kMaxTasks * kTaskRecordSize + kListHeadSize + kMaxDropCounters * 8 <= kMaxPayload &&
                  kDiagHeadSize + kMaxSlaves * kDiagRecordSize <= kMaxPayload && kSdoResultSize <= kMaxPayload &&
                  kListHeadSize + kMaxSlaves * kSlaveInfoRecordSize <= kMaxPayload &&
                  kListHeadSize + kMaxSlaves * kGraphRecordSize + kGraphRingSize <= kMaxPayload && kSiiSize <= kMaxPayload &&
                  kRegResultSize <= kMaxPayload && kSdoInfoResultSize <= kMaxPayload &&
                  kStatesResultSize <= kMaxPayload && kRescanResultSize <= kMaxPayload,
              "every payload fits");

constexpr double kPi = 3.14159265358979323846;

Error malformed(const char* what, std::size_t d0 = 0, std::size_t d1 = 0) noexcept {
  return make_error(Errc::malformed, what, static_cast<std::uint32_t>(d0), static_cast<std::uint32_t>(d1));
}

// A character a text field may hold (docs/protocol.md "Text fields"): printable ASCII.
bool is_text_char(char c) noexcept { return c >= 0x20 && c < 0x7F; }

bool within(double v, double lo, double hi) noexcept { return std::isfinite(v) && v >= lo && v <= hi; }

bool valid_mode(std::uint8_t mode) noexcept {
  return mode == static_cast<std::uint8_t>(ControlMode::cyclic_position) ||
         mode == static_cast<std::uint8_t>(ControlMode::cyclic_velocity) ||
         mode == static_cast<std::uint8_t>(ControlMode::cyclic_torque);
}

// A message's layout is written once, as a function template over the direction (`F`): its fields
// in wire order, each with its width, and, where a value is known, its checks. EncodeFields writes
// the fields and ignores the checks; DecodeFields reads them, runs the checks in the same order and
// keeps the first failure, so a datagram is judged by the first thing wrong with it on the wire.
// Widths are explicit: a field whose type changes width fails to compile instead of changing the wire.
// Layouts look alike in places (runs of f.u64(...) lines): each line is a field of its own record, in
// its place on the wire, with the checks in the order that decides a datagram's error. That is the
// table's data, written as code so that nested records, lists and checks stay in wire order; a
// descriptor table would be the same line per field plus member pointers of many types.
class EncodeFields {
 public:
  explicit EncodeFields(ByteSpan out) noexcept : w_(out) {}
  template <typename T>
  void u8(const T& v) noexcept { put<std::uint8_t>(v); }
  template <typename T>
  void u16(const T& v) noexcept { put<std::uint16_t>(v); }
  template <typename T>
  void u32(const T& v) noexcept { put<std::uint32_t>(v); }
  template <typename T>
  void u64(const T& v) noexcept { put<std::uint64_t>(v); }
  void f64(double v) noexcept { w_.f64(v); }
  template <std::size_t N>
  void f64s(const std::array<double, N>& values) noexcept {
    for (const double v : values) w_.f64(v);
  }
  // A NUL-padded text field: its printable ASCII up to the first NUL (any other byte sent as '?',
  // docs/protocol.md "Text fields"), then NUL to the end: the last byte always NUL.
  template <std::size_t N>
  void text(const std::array<char, N>& t, const char* /*unterminated*/) noexcept {
    std::size_t i = 0;
    for (; i + 1 < N && t[i] != '\0'; ++i) w_.u8(is_text_char(t[i]) ? static_cast<std::uint8_t>(t[i]) : std::uint8_t{'?'});
    w_.zeros(N - i);
  }
  void reserved(std::size_t count) noexcept { w_.zeros(count); }
  // A fixed-size byte field (all N bytes on the wire).
  template <std::size_t N>
  void bytes(const std::array<std::uint8_t, N>& b) noexcept { w_.bytes(b.data(), N); }
  void magic() noexcept { w_.bytes(kMagic.data(), kMagic.size()); }
  // A list's record count, at most `max` on the wire.
  void count(std::uint8_t v, std::size_t max) noexcept { w_.u8(static_cast<std::uint8_t>(v <= max ? v : max)); }
  // Checks, lengths and looking ahead are the decoder's.
  void ahead(std::uint8_t /*v*/, std::size_t /*offset*/) noexcept {}
  void length(std::size_t /*expected*/) noexcept {}
  void at_least(std::size_t /*head*/, const char* /*what*/) noexcept {}
  void check(bool /*ok*/, const char* /*what*/) noexcept {}
  void require(bool /*ok*/, Errc /*code*/, const char* /*what*/, std::size_t /*d0*/ = 0, std::size_t /*d1*/ = 0) noexcept {}

  bool ok() const noexcept { return w_.ok(); }
  std::size_t size() const noexcept { return w_.size(); }

 private:
  template <typename W, typename T>
  void put(const T& v) noexcept {
    static_assert(sizeof(T) == sizeof(W), "a field's type has its wire width");
    const auto x = static_cast<W>(v);
    if constexpr (sizeof(W) == 1) {
      w_.u8(x);
    } else if constexpr (sizeof(W) == 2) {
      w_.u16(x);
    } else if constexpr (sizeof(W) == 4) {
      w_.u32(x);
    } else {
      w_.u64(x);
    }
  }

  LeWriter w_;
};

class DecodeFields {
 public:
  // `reserved_what`: the error of a reserved byte that is not zero.
  explicit DecodeFields(ConstByteSpan in, const char* reserved_what = "reserved bytes not zero") noexcept
      : r_(in), size_(in.size()), reserved_what_(reserved_what) {}
  template <typename T>
  void u8(T& v) noexcept { v = get<std::uint8_t, T>(); }
  template <typename T>
  void u16(T& v) noexcept { v = get<std::uint16_t, T>(); }
  template <typename T>
  void u32(T& v) noexcept { v = get<std::uint32_t, T>(); }
  template <typename T>
  void u64(T& v) noexcept { v = get<std::uint64_t, T>(); }
  void f64(double& v) noexcept { v = r_.f64(); }
  template <std::size_t N>
  void f64s(std::array<double, N>& values) noexcept {
    std::generate(values.begin(), values.end(), [this] { return r_.f64(); });
  }
  // A text field holds printable ASCII, then NUL padding to its end (docs/protocol.md "Text fields"):
  // a control character (a terminal escape) or a byte after the first NUL is malformed.
  template <std::size_t N>
  void text(std::array<char, N>& t, const char* unterminated) noexcept {
    r_.chars(t.data(), N);
    require(t[N - 1] == '\0', Errc::malformed, unterminated);
    const auto end = std::find(t.begin(), t.end(), '\0');
    require(std::all_of(t.begin(), end, is_text_char) && std::all_of(end, t.end(), [](char c) { return c == '\0'; }),
            Errc::malformed, "text field holds other than printable ASCII and NUL padding");
  }
  void reserved(std::size_t count) noexcept { require(r_.zeros(count), Errc::malformed, reserved_what_); }
  template <std::size_t N>
  void bytes(std::array<std::uint8_t, N>& b) noexcept {
    std::generate(b.begin(), b.end(), [this] { return r_.u8(); });
  }
  void magic() noexcept {
    bool same = true;
    for (const std::uint8_t b : kMagic) same = r_.u8() == b && same;
    require(same, Errc::malformed, "bad magic");
  }
  void count(std::uint8_t& v, std::size_t /*max: checked by the layout, after the reserved bytes*/) noexcept { v = r_.u8(); }
  // A u8 further on, at `offset` from the start (0 when it is not there), read ahead of its turn.
  void ahead(std::uint8_t& v, std::size_t offset) noexcept { v = r_.peek(offset); }
  // The payload is exactly `expected` bytes long.
  void length(std::size_t expected) noexcept {
    require(size_ == expected, Errc::malformed, "payload length differs from its type's", size_, expected);
  }
  // A list's head is there (its count says how long the rest is).
  void at_least(std::size_t head, const char* what) noexcept { require(size_ >= head, Errc::malformed, what, size_); }
  // A value inside its documented range.
  void check(bool ok, const char* what) noexcept { require(ok, Errc::out_of_range, what); }
  void require(bool ok, Errc code, const char* what, std::size_t d0 = 0, std::size_t d1 = 0) noexcept {
    if (!ok && status_.ok()) {
      status_ = make_error(code, what, static_cast<std::uint32_t>(d0), static_cast<std::uint32_t>(d1));
    }
  }

  // The first failure; a layout that read other than the whole input is malformed (never, when the
  // layouts' lengths are right: this is the guard that keeps them so).
  Status status() noexcept {
    require(r_.ok() && r_.size() == size_, Errc::malformed, "payload length differs from its fields", size_, r_.size());
    return status_;
  }

 private:
  template <typename W, typename T>
  T get() noexcept {
    static_assert(sizeof(T) == sizeof(W), "a field's type has its wire width");
    if constexpr (sizeof(W) == 1) {
      return static_cast<T>(r_.u8());
    } else if constexpr (sizeof(W) == 2) {
      return static_cast<T>(r_.u16());
    } else if constexpr (sizeof(W) == 4) {
      return static_cast<T>(r_.u32());
    } else {
      return static_cast<T>(r_.u64());
    }
  }

  LeReader r_;
  std::size_t size_;
  const char* reserved_what_;
  Status status_{};
};

// Records of a list to walk: its count, never more than the protocol holds.
std::size_t records(std::uint8_t count, std::size_t max) noexcept { return count <= max ? count : max; }

// The header (kHeaderSize bytes), both directions; parse_frame's structure checks, in wire order.
template <typename F, typename H>
void header_fields(F& f, H& h) noexcept {
  f.magic();
  f.u8(h.version);
  f.require(h.version == kVersion, Errc::malformed, "unsupported protocol version", h.version, kVersion);
  f.u8(h.type);
  f.u8(h.flags);
  f.require(h.flags == 0, Errc::malformed, "reserved header bytes not zero");
  f.reserved(1);
  f.u32(h.sender);
  f.u32(h.robot);
  f.u64(h.epoch);
  f.u64(h.sequence);
  f.u16(h.payload_length);
  f.reserved(6);
  // Only get_epoch may leave the robot and the epoch open; the robot's epoch answer never does.
  const bool asks_epoch = h.type == MessageType::get_epoch;
  f.require(!asks_epoch || h.epoch == 0, Errc::malformed, "get_epoch with an epoch");
  f.require(asks_epoch || (h.epoch != 0 && h.robot != kAnyRobot), Errc::malformed, "no robot id or no epoch");
  f.require(h.payload_length <= kMaxPayload, Errc::capacity_exceeded, "payload length above the protocol's maximum",
            h.payload_length, kMaxPayload);
}

// The payload layouts, one per message (docs/protocol.md), in the order of kLayouts.
template <typename F, typename M>
void no_payload(F& f, M& /*m*/) noexcept {
  f.length(0);
}

template <typename F>
void joint_mask_checks(F& f, JointMask joints) noexcept {
  f.check(joints != 0, "no joint selected");
  f.check((joints & ~kAllJoints) == 0, "joint mask names a joint the robot does not have");
}

template <typename F, typename M>
void joints_fields(F& f, M& m) noexcept {
  f.length(kJointsSize);
  f.u32(m.joints.joints);
  joint_mask_checks(f, m.joints.joints);
}

template <typename F, typename M>
void select_mode_fields(F& f, M& m) noexcept {
  f.length(kSelectModeSize);
  f.u32(m.joints.joints);
  f.u8(m.joints.mode);
  f.reserved(3);
  f.check(valid_mode(static_cast<std::uint8_t>(m.joints.mode)), "mode must be CSP (8), CSV (9) or CST (10)");
  joint_mask_checks(f, m.joints.joints);
}

template <typename F, typename M>
void move_fields(F& f, M& m) noexcept {
  f.length(kMoveSize);
  f.u8(m.move.task);
  f.u8(m.move.effector);
  f.reserved(6);
  f.f64s(m.move.position_m);
  f.f64s(m.move.rpy_rad);
  f.check(m.move.task < kMaxRcTasks, "RC task index");
  f.check(static_cast<std::uint8_t>(m.move.effector) <= 1, "effector");
  for (const double v : m.move.position_m) f.check(within(v, -kMaxReachM, kMaxReachM), "position beyond the robot's reach");
  for (const double v : m.move.rpy_rad) f.check(within(v, -kPi, kPi), "orientation angle outside [-pi, pi]");
}

template <typename F, typename M>
void hand_fields(F& f, M& m) noexcept {
  f.length(kHandSize);
  f.u8(m.hand.task);
  f.u8(m.hand.hand);
  f.u8(m.hand.action);
  f.reserved(1);
  f.check(m.hand.task < kMaxRcTasks, "RC task index");
  f.check(static_cast<std::uint8_t>(m.hand.hand) <= 1, "hand");
  f.check(static_cast<std::uint8_t>(m.hand.action) <= 1, "hand action");
}

template <typename F, typename M>
void owner_fields(F& f, M& m) noexcept {
  f.length(kOwnerSize);
  f.u8(m.owner.task);
  f.reserved(3);
  f.check(m.owner.task < kMaxRcTasks, "RC task index");
}

template <typename F, typename M>
void imu_fields(F& f, M& m) noexcept {
  f.length(kImuSize);
  f.u64(m.imu.time_unix_ns);
  f.f64s(m.imu.orientation_wxyz);
  f.f64s(m.imu.angular_velocity_rad_s);
  f.f64s(m.imu.linear_acceleration_m_s2);
  double norm2 = 0.0;
  bool components = true;
  for (const double v : m.imu.orientation_wxyz) {
    components = components && within(v, -1.0 - kQuaternionNormTolerance, 1.0 + kQuaternionNormTolerance);
    norm2 += v * v;
  }
  f.check(components, "quaternion component");
  f.check(!components || std::fabs(std::sqrt(norm2) - 1.0) <= kQuaternionNormTolerance, "quaternion not of unit norm");
  for (const double v : m.imu.angular_velocity_rad_s) {
    f.check(within(v, -kMaxAngularVelocityRadS, kMaxAngularVelocityRadS), "angular velocity");
  }
  for (const double v : m.imu.linear_acceleration_m_s2) {
    f.check(within(v, -kMaxAccelerationMs2, kMaxAccelerationMs2), "linear acceleration");
  }
}

template <typename F, typename M>
void gps_fields(F& f, M& m) noexcept {
  f.length(kGpsSize);
  f.u64(m.gps.time_unix_ns);
  f.f64(m.gps.latitude_deg);
  f.f64(m.gps.longitude_deg);
  f.f64(m.gps.altitude_m);
  f.f64(m.gps.horizontal_accuracy_m);
  f.f64(m.gps.vertical_accuracy_m);
  f.u8(m.gps.fix);
  f.u8(m.gps.satellites);
  f.reserved(6);
  f.check(within(m.gps.latitude_deg, -90.0, 90.0), "latitude");
  f.check(within(m.gps.longitude_deg, -180.0, 180.0), "longitude");
  f.check(within(m.gps.altitude_m, -1000.0, 10000.0), "altitude");
  f.check(within(m.gps.horizontal_accuracy_m, 0.0, 10000.0), "horizontal accuracy");
  f.check(within(m.gps.vertical_accuracy_m, 0.0, 10000.0), "vertical accuracy");
  f.check(static_cast<std::uint8_t>(m.gps.fix) <= static_cast<std::uint8_t>(GpsFix::rtk), "fix type");
}

template <typename F, typename M>
void reply_fields(F& f, M& m) noexcept {
  f.length(kReplySize);
  f.u64(m.reply.request_sequence);
  f.u8(m.reply.request_type);
  f.u8(m.reply.outcome);
  f.u8(m.reply.reason);
  f.reserved(1);
  f.u32(m.reply.refused_joints);
  f.text(m.reply.text, "reply text not NUL-terminated");
  for (std::size_t j = 0; j < kJointCount; ++j) {
    auto& jr = m.reply.joint_refusals[j];
    f.u8(jr.why);
    f.u8(jr.state);
    f.u8(jr.input);
    f.reserved(1);
    f.check(static_cast<std::uint8_t>(jr.why) <= kJointRefusalLast, "joint refusal");
    f.check(jr.state < fsm::kJointStateCount && jr.input < fsm::kJointInputCount, "joint state or input");
    f.check(jr.why == JointRefusal::none || (m.reply.refused_joints & joint_bit(j)) != 0, "joint refusal of a joint not refused");
  }
  f.check(is_known(static_cast<std::uint8_t>(m.reply.request_type)), "request type");
  f.check(static_cast<std::uint8_t>(m.reply.outcome) <= 1, "outcome");
  f.check(static_cast<std::uint8_t>(m.reply.reason) <= static_cast<std::uint8_t>(RefusalReason::sender_table_full),
          "refusal reason");
  f.check((m.reply.refused_joints & ~kAllJoints) == 0, "refused joint mask");
}

// How old an answer's figures are (FiguresAge; DiagPayload's own two fields): flags (bit 0 stale), 2
// reserved bytes, the age in ms; in the 7 bytes after the answer's first field (status, slaves,
// master, tasks, diag, owner_state, slave_info, graph).
template <typename F, typename A>
void age_fields(F& f, A& age) noexcept {
  std::uint8_t flags = age.stale ? kFiguresStale : std::uint8_t{0};
  f.u8(flags);
  f.reserved(2);
  f.u32(age.age_ms);
  f.check((flags & ~kFiguresStale) == 0, "figures flags");
  if constexpr (!std::is_const_v<A>) age.stale = (flags & kFiguresStale) != 0;
}

template <typename F, typename M>
void status_fields(F& f, M& m) noexcept {
  f.length(kStatusSize);
  f.u64(m.status.cycle);
  std::uint8_t count = kJointCount;  // on the wire for the reader; always every joint
  f.u8(count);
  age_fields(f, m.status.age);
  f.check(count == kJointCount, "joint count");
  for (auto& j : m.status.joints) {
    f.u8(j.state);
    f.u8(j.mode);
    f.u8(j.flags);
    f.u8(j.fault);
    f.u8(j.owner);
    f.reserved(3);
    f.f64(j.position_rad);
    f.f64(j.velocity_rad_s);
    f.f64(j.torque_nm);
    f.check(j.state <= 4 && (j.flags & ~kJointFlagsMask) == 0 && is_valid_fault_reason(j.fault), "joint status field");
    f.check(j.owner == kNoOwner || j.owner < kMaxRcTasks, "owner");
  }
}

// A list's head: its count (at most `max`) and 7 bytes (`seven`: reserved, or a slaves answer's
// FiguresAge), then `head - 8` more bytes of the caller's. Returns the records to walk; the caller
// checks the length they make.
template <typename F, typename C, typename Seven>
std::size_t list_head(F& f, C& count, std::size_t max, std::size_t head, const char* short_what,
                      const char* count_what, Seven seven) noexcept {
  f.at_least(head, short_what);
  f.count(count, max);
  seven();
  f.check(count <= max, count_what);
  return records(count, max);
}
template <typename F, typename C>
std::size_t list_head(F& f, C& count, std::size_t max, std::size_t head, const char* short_what,
                      const char* count_what) noexcept {
  return list_head(f, count, max, head, short_what, count_what, [&f] { f.reserved(7); });
}

// A list of slaves with the handler's FiguresAge in its head (slaves, slave_info, graph): `each`
// reads or writes one record of `record_size` bytes; `tail` bytes follow the records (graph's ring).
template <typename F, typename P, typename Each>
void slave_list_fields(F& f, P& payload, std::size_t record_size, Each each, std::size_t tail = 0) noexcept {
  const std::size_t count = list_head(f, payload.count, kMaxSlaves, kListHeadSize, "payload shorter than its list header",
                                      "slave count", [&f, &payload] { age_fields(f, payload.age); });
  f.length(kListHeadSize + count * record_size + tail);
  for (std::size_t i = 0; i < count; ++i) each(payload.slaves[i]);
}

template <typename F, typename M>
void slaves_fields(F& f, M& m) noexcept {
  slave_list_fields(f, m.slaves, kSlaveRecordSize, [&f](auto& s) {
    f.u16(s.position);
    f.u16(s.station);
    f.u8(s.al_state);
    f.u8(s.flags);
    f.reserved(2);
    f.text(s.name, "slave name not NUL-terminated");
    f.check((s.flags & ~kSlaveFlagsMask) == 0, "slave flags");
    f.u8(s.recovery);
    f.reserved(3);
    f.u32(s.recovery_age_ms);
    f.check(s.recovery < kRecoveryStates, "slave recovery state");
  });
}

template <typename F, typename M>
void master_fields(F& f, M& m) noexcept {
  f.length(kMasterSize);
  f.u8(m.master.state);
  age_fields(f, m.master.age);
  f.u64(m.master.cycles);
  f.u64(m.master.frames_sent);
  f.u64(m.master.frames_lost);
  f.u64(m.master.late_periods);
  f.u64(m.master.dc_deviation_ns);
  f.u64(m.master.dc_max_deviation_ns);
  f.u64(m.master.datagrams_accepted);
  for (auto& v : m.master.rejected) f.u64(v);
  f.check(m.master.state <= 4, "master state");
}

template <typename F, typename M>
void epoch_fields(F& f, M& m) noexcept {
  f.length(kEpochSize);
  f.u64(m.epoch.request_sequence);
}

template <typename F, typename T>
void timing_fields(F& f, T& t) noexcept {
  f.u32(t.min);
  f.u32(t.mean);
  f.u32(t.stddev);
  f.u32(t.max);
  f.u32(t.p99);
  f.u32(t.p999);
  f.u32(t.p9999);
}

template <typename F, typename M>
void tasks_fields(F& f, M& m) noexcept {
  const std::size_t count = list_head(f, m.tasks.count, kMaxTasks, kListHeadSize, "payload shorter than its list header",
                                      "task count", [&f, &m] { age_fields(f, m.tasks.age); });
  // The queues' drop counters follow the records: their count is checked before a record is read.
  const std::size_t drops_at = kListHeadSize + count * kTaskRecordSize;
  f.at_least(drops_at + kListHeadSize, "payload shorter than its drop counters' header");
  f.ahead(m.tasks.drop_count, drops_at);
  f.check(m.tasks.drop_count <= kMaxDropCounters, "drop counter count");
  const std::size_t drops = records(m.tasks.drop_count, kMaxDropCounters);
  f.length(drops_at + kListHeadSize + drops * 8);
  for (std::size_t i = 0; i < count; ++i) {
    auto& t = m.tasks.tasks[i];
    f.text(t.name, "task name not NUL-terminated");
    f.u32(t.pid);
    f.u16(t.cpu);
    f.u16(t.priority);
    f.u8(t.policy);
    f.reserved(1);
    f.u16(t.table_cpu);
    f.u16(t.table_priority);
    f.u16(t.restarts);
    f.u32(t.tid);
    f.u32(t.uptime_ms);
    f.u64(t.periods);
    f.u64(t.missed);
    f.u64(t.max_execution_ns);
    timing_fields(f, t.execution);
    timing_fields(f, t.latency);
  }
  f.count(m.tasks.drop_count, kMaxDropCounters);
  f.reserved(7);
  for (std::size_t i = 0; i < drops; ++i) f.u64(m.tasks.dropped[i]);
}

template <typename F, typename M>
void diag_fields(F& f, M& m) noexcept {
  const std::size_t count = list_head(f, m.diag.count, kMaxSlaves, kDiagHeadSize, "payload shorter than its diag header",
                                      "slave count", [&f, &m] { age_fields(f, m.diag); });
  f.length(kDiagHeadSize + count * kDiagRecordSize);
  f.u64(m.diag.cycle);
  f.u64(m.diag.sweeps);
  for (std::size_t i = 0; i < count; ++i) {
    auto& d = m.diag.slaves[i];
    for (auto& p : d.ports) {
      f.u16(p.invalid_frames);
      f.u16(p.rx_errors);
      f.u16(p.forwarded_errors);
      f.u16(p.lost_links);
    }
    f.u16(d.processing_unit_errors);
    f.u16(d.pdi_errors);
    f.u16(d.reads);
    f.u8(d.warned);
    f.u8(d.warned_before);
    f.check(((d.warned | d.warned_before) & ~kDiagWarnedMask) == 0, "warned ports");
  }
}

template <typename F, typename M>
void version_fields(F& f, M& m) noexcept {
  f.length(kVersionSize);
  f.text(m.version.program, "program version not NUL-terminated");
  f.u32(m.version.layout_version);
  f.u32(m.version.layout_hash);
  f.text(m.version.build_type, "build type not NUL-terminated");
}

template <typename F, typename M>
void owner_state_fields(F& f, M& m) noexcept {
  f.length(kOwnerStateSize);
  f.u8(m.owner_state.owner);
  age_fields(f, m.owner_state.age);
  f.u64(m.owner_state.generation);
  f.check(m.owner_state.owner < kMaxRcTasks || m.owner_state.owner == kNoOwner, "owner task");
  for (auto& t : m.owner_state.tasks) {
    f.u8(t.present);
    f.u8(t.alive);
    f.u8(t.phase);
    f.u8(t.mode);
    f.u32(t.heartbeat_age_ms);
    f.check(t.present <= 1 && t.alive <= 1, "RC task flags");
  }
}

// Whom a transfer addresses (SdoTarget): a joint (slave 0) or a slave's position (joint 0).
template <typename F>
void sdo_target_checks(F& f, std::uint8_t joint, SdoTarget target, std::uint8_t slave) noexcept {
  f.check(static_cast<std::uint8_t>(target) <= kSdoTargetLast, "sdo target kind");
  if (target == SdoTarget::slave) {
    f.check(joint == 0 && slave < kMaxSlaves, "slave position (joint 0)");
  } else {
    f.check(joint < kJointCount && slave == 0, "joint index (slave 0)");
  }
}

// sdo_upload: joint, subindex, index, target kind, slave position, 2 reserved bytes. sdo_download:
// joint, subindex, index, the size, target kind, slave position and the value in a fixed 256-byte
// field (bytes past the size zero).
template <typename F, typename M>
void sdo_address_fields(F& f, M& m) noexcept {
  f.u8(m.sdo.joint);
  f.u8(m.sdo.subindex);
  f.u16(m.sdo.index);
  f.check(m.sdo.index != 0, "object index 0");
}

template <typename F, typename M>
void sdo_target_fields(F& f, M& m) noexcept {
  f.u8(m.sdo.target);
  f.u8(m.sdo.slave);
  sdo_target_checks(f, m.sdo.joint, m.sdo.target, m.sdo.slave);
}

template <typename F, typename M>
void sdo_upload_fields(F& f, M& m) noexcept {
  f.length(kSdoUploadSize);
  sdo_address_fields(f, m);
  sdo_target_fields(f, m);
  f.reserved(2);
}

template <typename F, typename M>
void sdo_download_fields(F& f, M& m) noexcept {
  f.length(kSdoDownloadSize);
  sdo_address_fields(f, m);
  f.u16(m.sdo.size);
  sdo_target_fields(f, m);
  f.bytes(m.sdo.data);
  f.check(m.sdo.size >= 1 && m.sdo.size <= kSdoDataSize, "value size (1..256 bytes)");
  bool padding_zero = true;
  for (std::size_t i = m.sdo.size; i < kSdoDataSize; ++i) padding_zero = padding_zero && m.sdo.data[i] == 0;
  f.require(padding_zero, Errc::malformed, "bytes past the value's size not zero");
}

template <typename F, typename M>
void sdo_result_fields(F& f, M& m) noexcept {
  f.length(kSdoResultSize);
  auto& r = m.sdo_result;
  f.u64(r.request_sequence);
  f.u8(r.request_type);
  f.u8(r.joint);
  f.u8(r.subindex);
  f.u8(r.status);
  f.u16(r.index);
  f.u16(r.size);
  f.u32(r.abort_code);
  f.u16(r.mailbox_error);
  f.u8(r.al_state);
  f.u8(r.flags);
  f.u32(r.exchanges);
  f.u8(r.target);
  f.u8(r.slave);
  f.reserved(2);
  f.text(r.text, "sdo result text not NUL-terminated");
  f.bytes(r.data);
  f.check(r.request_type == MessageType::sdo_upload || r.request_type == MessageType::sdo_download, "sdo request type");
  sdo_target_checks(f, r.joint, r.target, r.slave);
  f.check(static_cast<std::uint8_t>(r.status) <= kSdoStatusLast, "sdo status");
  f.check(r.size <= kSdoDataSize, "value size");
  f.check((r.flags & ~kSdoSegmented) == 0, "sdo result flags");
}

template <typename F, typename M>
void slave_info_fields(F& f, M& m) noexcept {
  slave_list_fields(f, m.slave_info, kSlaveInfoRecordSize, [&f](auto& s) {
    f.u16(s.position);
    f.u16(s.station);
    f.u32(s.vendor_id);
    f.u32(s.product_code);
    f.u32(s.revision);
    f.u32(s.serial_number);
    f.u16(s.al_status);
    f.u16(s.al_status_code);
    f.u8(s.flags);
    f.reserved(3);
    f.check(s.position < kMaxSlaves, "slave position");
    f.check((s.flags & ~kSlaveInfoFlagsMask) == 0, "slave info flags");
  });
}

template <typename F, typename M>
void graph_fields(F& f, M& m) noexcept {
  slave_list_fields(f, m.graph, kGraphRecordSize, [&f](auto& g) {
    f.u8(g.position);
    f.u8(g.upstream);
    f.u8(g.upstream_port);
    f.u8(g.kind);
    f.u16(g.station);
    f.u8(g.joint);
    f.u8(g.branch);
    f.u8(g.al_state);
    f.u8(g.flags);
    f.u8(g.recovery);
    f.reserved(1);
    f.check(g.position < kMaxSlaves, "slave position");
    f.check(g.upstream == kGraphNone || g.upstream < g.position, "upstream slave (comes earlier in frame order)");
    f.check(g.upstream_port < kDiagPorts && g.kind <= 1, "upstream port or slave kind");
    f.check(g.joint == kGraphNone || g.joint < kJointCount, "joint index");
    f.check((g.flags & ~kSlaveFlagsMask) == 0, "slave flags");
    f.check(g.recovery < kRecoveryStates, "slave recovery state");
  }, kGraphRingSize);
  auto& ring = m.graph.ring;
  f.u8(ring.state);
  f.u8(ring.before);
  f.u8(ring.after);
  f.u8(ring.return_slave);
  f.u8(ring.return_port);
  f.u8(ring.transients);
  f.u16(ring.breaks);
  f.u16(ring.repairs);
  f.reserved(2);
  f.check(ring.state <= kRingStateLost, "ring state");
  const auto place = [](std::uint8_t p) { return p < kMaxSlaves || p == kRingMainPort || p == kRingRingPort; };
  f.check(place(ring.before) && place(ring.after), "ring break place (a slave position or a master port)");
  f.check((ring.return_slave == kGraphNone || ring.return_slave < kMaxSlaves) && ring.return_port < kDiagPorts,
          "ring-return slave or port");
}

template <typename F, typename M>
void diag_reset_fields(F& f, M& m) noexcept {
  f.length(kDiagResetSize);
  f.u32(m.diag_reset.slaves);
  f.check(m.diag_reset.slaves != 0, "no slave selected");
  f.check((m.diag_reset.slaves >> kMaxSlaves) == 0, "slave mask names a slave the robot does not have");
}

// get_sii: slave position, 1 reserved byte, offset into the image.
template <typename F, typename M>
void sii_request_fields(F& f, M& m) noexcept {
  f.length(kSiiRequestSize);
  f.u8(m.sii_request.slave);
  f.reserved(1);
  f.u16(m.sii_request.offset);
  f.check(m.sii_request.slave < kMaxSlaves, "slave position");
  f.check(m.sii_request.offset < kSiiImageBytes, "offset into the SII image");
}

// sii: slave position, flags, the image's size, this chunk's offset and length, then the chunk in
// a fixed kSiiChunkBytes field (bytes past the length zero).
template <typename F, typename M>
void sii_fields(F& f, M& m) noexcept {
  f.length(kSiiSize);
  auto& c = m.sii;
  f.u8(c.slave);
  f.u8(c.flags);
  f.u16(c.size);
  f.u16(c.offset);
  f.u16(c.length);
  f.bytes(c.bytes);
  f.check(c.slave < kMaxSlaves, "slave position");
  f.check((c.flags & ~kSiiFlagsMask) == 0, "SII flags");
  f.check(c.size <= kSiiImageBytes && c.length <= kSiiChunkBytes, "SII image or chunk size");
  f.check(std::size_t{c.offset} + c.length <= c.size || (c.length == 0 && c.offset <= c.size), "SII chunk past the image");
  bool padding_zero = true;
  for (std::size_t i = c.length; i < kSiiChunkBytes; ++i) padding_zero = padding_zero && c.bytes[i] == 0;
  f.require(padding_zero, Errc::malformed, "bytes past the chunk's length not zero");
}

// reg_read: slave position, 1 reserved byte, first register's address, length (1..kRegDataSize),
// 2 reserved bytes; the range ends at 0xFFFF at most.
template <typename F, typename M>
void reg_read_fields(F& f, M& m) noexcept {
  f.length(kRegReadSize);
  auto& r = m.reg_read;
  f.u8(r.slave);
  f.reserved(1);
  f.u16(r.address);
  f.u16(r.length);
  f.reserved(2);
  f.check(r.slave < kMaxSlaves, "slave position");
  f.check(r.length >= 1 && r.length <= kRegDataSize, "register read length");
  f.check(std::size_t{r.address} + r.length <= 0x10000U, "register range past 0xFFFF");
}

// reg_result: request sequence, slave, status, address, length, working counter, frames, 7
// reserved bytes, then the data in a fixed kRegDataSize field (bytes past the length zero).
template <typename F, typename M>
void reg_result_fields(F& f, M& m) noexcept {
  f.length(kRegResultSize);
  auto& r = m.reg_result;
  f.u64(r.request_sequence);
  f.u8(r.slave);
  f.u8(r.status);
  f.u16(r.address);
  f.u16(r.length);
  f.u16(r.wkc);
  f.u8(r.frames);
  f.reserved(7);
  f.bytes(r.data);
  f.check(r.slave < kMaxSlaves, "slave position");
  f.check(static_cast<std::uint8_t>(r.status) <= kRegStatusLast, "register read status");
  f.check(r.length <= kRegDataSize, "register read length");
  f.check(std::size_t{r.address} + r.length <= 0x10000U, "register range past 0xFFFF");
  bool padding_zero = true;
  for (std::size_t i = r.length; i < kRegDataSize; ++i) padding_zero = padding_zero && r.data[i] == 0;
  f.require(padding_zero, Errc::malformed, "bytes past the read's length not zero");
}

// An SDO Information request (sdo_info, and echoed in its result): target kind, joint, slave
// position, request (1 OD list, 3 object description, 5 entry description), index, subindex, 1
// reserved byte, offset into the response's data, 2 reserved bytes.
template <typename F, typename R>
void sdo_info_request_fields(F& f, R& r) noexcept {
  f.u8(r.target);
  f.u8(r.joint);
  f.u8(r.slave);
  f.u8(r.op);
  f.u16(r.index);
  f.u8(r.subindex);
  f.reserved(1);
  f.u16(r.offset);
  f.reserved(2);
  sdo_target_checks(f, r.joint, r.target, r.slave);
  f.check(r.op == SdoInfoOp::od_list || r.op == SdoInfoOp::object_description || r.op == SdoInfoOp::entry_description,
          "sdo information request");
  f.check(r.op != SdoInfoOp::od_list || (r.index >= 1 && r.index <= 5), "OD list type (1..5)");
  f.check(r.op == SdoInfoOp::entry_description || r.subindex == 0, "subindex of an OD list or object request");
  f.check(r.op == SdoInfoOp::od_list || r.offset == 0, "offset of an object or entry request");
}

template <typename F, typename M>
void sdo_info_fields(F& f, M& m) noexcept {
  f.length(kSdoInfoSize);
  sdo_info_request_fields(f, m.sdo_info);
}

// sdo_info_result: request sequence, the request (12 bytes as sdo_info), status, 3 reserved bytes,
// abort code, mailbox error, length, total, 2 reserved bytes, exchanges, 4 reserved bytes, the
// text, then the data in a fixed kSdoDataSize field (bytes past the length zero).
template <typename F, typename M>
void sdo_info_result_fields(F& f, M& m) noexcept {
  f.length(kSdoInfoResultSize);
  auto& r = m.sdo_info_result;
  f.u64(r.request_sequence);
  sdo_info_request_fields(f, r.request);
  f.u8(r.status);
  f.reserved(3);
  f.u32(r.abort_code);
  f.u16(r.mailbox_error);
  f.u16(r.length);
  f.u16(r.total);
  f.reserved(2);
  f.u32(r.exchanges);
  f.reserved(4);
  f.text(r.text, "sdo information result text not NUL-terminated");
  f.bytes(r.data);
  f.check(static_cast<std::uint8_t>(r.status) <= kSdoStatusLast, "sdo status");
  f.check(r.length <= kSdoDataSize, "sdo information data length");
  f.check(std::size_t{r.request.offset} + r.length <= r.total || r.length == 0, "sdo information data past the response");
  bool padding_zero = true;
  for (std::size_t i = r.length; i < kSdoDataSize; ++i) padding_zero = padding_zero && r.data[i] == 0;
  f.require(padding_zero, Errc::malformed, "bytes past the data's length not zero");
}

// states: the slaves (a mask of planned positions, at least one), the AL state (1, 2, 4 or 8), 3
// reserved bytes.
template <typename F, typename M>
void states_fields(F& f, M& m) noexcept {
  f.length(kStatesSize);
  auto& r = m.states;
  f.u32(r.slaves);
  f.u8(r.state);
  f.reserved(3);
  f.check(r.slaves != 0 && (r.slaves >> kMaxSlaves) == 0, "slaves of a states request");
  f.check(is_requestable_al_state(r.state), "AL state of a states request");
}

// states_result: request sequence, slaves, state, status, 2 reserved, joints in service, frames, 2
// reserved; then per slave position (kMaxSlaves) its outcome, 1 reserved, AL status, AL status
// code: zero for a slave not in the request.
template <typename F, typename M>
void states_result_fields(F& f, M& m) noexcept {
  f.length(kStatesResultSize);
  auto& r = m.states_result;
  f.u64(r.request_sequence);
  f.u32(r.slaves);
  f.u8(r.state);
  f.u8(r.status);
  f.reserved(2);
  f.u32(r.in_service);
  f.u16(r.frames);
  f.reserved(2);
  bool others_zero = true;
  bool outcomes_known = true;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    auto& rec = r.records[p];
    f.u8(rec.outcome);
    f.reserved(1);
    f.u16(rec.al_status);
    f.u16(rec.al_code);
    outcomes_known = outcomes_known && static_cast<std::uint8_t>(rec.outcome) <= kStateOutcomeLast;
    const bool in_request = ((r.slaves >> p) & 1U) != 0;
    others_zero = others_zero && (in_request || (static_cast<std::uint8_t>(rec.outcome) == 0 && rec.al_status == 0 && rec.al_code == 0));
  }
  f.check(r.slaves != 0 && (r.slaves >> kMaxSlaves) == 0, "slaves of a states request");
  f.check(is_requestable_al_state(r.state), "AL state of a states request");
  f.check(static_cast<std::uint8_t>(r.status) <= kStatesStatusLast, "states status");
  f.check((r.in_service & ~kAllJoints) == 0, "joints in service");
  f.check(outcomes_known, "a slave's states outcome");
  f.require(others_zero, Errc::malformed, "a record of a slave outside the request not zero");
}

// rescan: 4 reserved bytes.
template <typename F, typename M>
void rescan_fields(F& f, M& /*m*/) noexcept {
  f.length(kRescanSize);
  f.reserved(4);
}

// rescan_result: request sequence, status, devices counted (the BRD's working counter), devices read
// (<= kRescanDevices), differences (<= kRescanDifferences), frames, 10 reserved; then kRescanDevices
// device records of 20 (vendor, product, revision, serial, alias, planned slot (0..22 or 0xFF),
// identified (0 or 1)) and kRescanDifferences difference records of 4 (kind, planned (0..22 or
// 0xFF), found (a device read, or 0xFF), 1 reserved); records past their counts empty (numbers 0,
// positions 0xFF).
template <typename F, typename M>
void rescan_result_fields(F& f, M& m) noexcept {
  f.length(kRescanResultSize);
  auto& r = m.rescan_result;
  f.u64(r.request_sequence);
  f.u8(r.status);
  f.u8(r.counted);
  f.u8(r.devices);
  f.u8(r.differences);
  f.u16(r.frames);
  f.reserved(10);
  bool in_range = true;
  bool rest_zero = true;
  for (std::size_t i = 0; i < kRescanDevices; ++i) {
    auto& d = r.records[i];
    f.u32(d.vendor_id);
    f.u32(d.product_code);
    f.u32(d.revision);
    f.u32(d.serial_number);
    f.u16(d.station_alias);
    f.u8(d.slot);
    f.u8(d.identified);
    in_range = in_range && (d.slot < kMaxSlaves || d.slot == kNoPlace) && d.identified <= 1;
    if (i >= r.devices) {
      rest_zero = rest_zero && d.vendor_id == 0 && d.product_code == 0 && d.revision == 0 && d.serial_number == 0 &&
                  d.station_alias == 0 && d.slot == kNoPlace && d.identified == 0;
    }
  }
  for (std::size_t k = 0; k < kRescanDifferences; ++k) {
    auto& d = r.found_differences[k];
    f.u8(d.kind);
    f.u8(d.planned);
    f.u8(d.found);
    f.reserved(1);
    in_range = in_range && static_cast<std::uint8_t>(d.kind) <= kRescanDifferenceLast &&
               (d.planned < kMaxSlaves || d.planned == kNoPlace) && (d.found < r.devices || d.found == kNoPlace);
    if (k >= r.differences) {
      rest_zero = rest_zero && static_cast<std::uint8_t>(d.kind) == 0 && d.planned == kNoPlace && d.found == kNoPlace;
    }
  }
  f.check(static_cast<std::uint8_t>(r.status) <= kRescanStatusLast, "rescan status");
  f.check(r.devices <= kRescanDevices && r.differences <= kRescanDifferences, "rescan record counts");
  f.check(in_range, "a rescan record's field");
  f.require(rest_zero, Errc::malformed, "a rescan record past its count not empty");
}

// The table of message layouts: every type the protocol defines, its name and its payload's layout
// (each function above serves both directions). A new message is a row and a layout.
struct Layout {
  MessageType type;
  const char* name;
  void (*encode)(EncodeFields&, const Message&) noexcept;
  void (*decode)(DecodeFields&, Message&) noexcept;
};
constexpr Layout kLayouts[] = {
    {MessageType::get_status, "get_status", no_payload, no_payload},
    {MessageType::get_slaves, "get_slaves", no_payload, no_payload},
    {MessageType::get_master, "get_master", no_payload, no_payload},
    {MessageType::get_tasks, "get_tasks", no_payload, no_payload},
    {MessageType::get_diag, "get_diag", no_payload, no_payload},
    {MessageType::get_epoch, "get_epoch", no_payload, no_payload},
    {MessageType::get_version, "get_version", no_payload, no_payload},
    {MessageType::get_owner, "get_owner", no_payload, no_payload},
    {MessageType::get_graph, "get_graph", no_payload, no_payload},
    {MessageType::get_slave_info, "get_slave_info", no_payload, no_payload},
    {MessageType::get_sii, "get_sii", sii_request_fields, sii_request_fields},
    {MessageType::initialize, "initialize", joints_fields, joints_fields},
    {MessageType::enable, "enable", joints_fields, joints_fields},
    {MessageType::disable, "disable", joints_fields, joints_fields},
    {MessageType::hold, "hold", joints_fields, joints_fields},
    {MessageType::select_mode, "select_mode", select_mode_fields, select_mode_fields},
    {MessageType::clear_joints, "clear_joints", joints_fields, joints_fields},
    {MessageType::clear_moved, "clear_moved", joints_fields, joints_fields},
    {MessageType::diag_reset, "diag_reset", diag_reset_fields, diag_reset_fields},
    {MessageType::move_effector, "move_effector", move_fields, move_fields},
    {MessageType::hand, "hand", hand_fields, hand_fields},
    {MessageType::take_owner, "take_owner", owner_fields, owner_fields},
    {MessageType::sdo_upload, "sdo_upload", sdo_upload_fields, sdo_upload_fields},
    {MessageType::sdo_download, "sdo_download", sdo_download_fields, sdo_download_fields},
    {MessageType::reg_read, "reg_read", reg_read_fields, reg_read_fields},
    {MessageType::sdo_info, "sdo_info", sdo_info_fields, sdo_info_fields},
    {MessageType::states, "states", states_fields, states_fields},
    {MessageType::rescan, "rescan", rescan_fields, rescan_fields},
    {MessageType::imu, "imu", imu_fields, imu_fields},
    {MessageType::gps, "gps", gps_fields, gps_fields},
    {MessageType::reply, "reply", reply_fields, reply_fields},
    {MessageType::status, "status", status_fields, status_fields},
    {MessageType::slaves, "slaves", slaves_fields, slaves_fields},
    {MessageType::master, "master", master_fields, master_fields},
    {MessageType::tasks, "tasks", tasks_fields, tasks_fields},
    {MessageType::diag, "diag", diag_fields, diag_fields},
    {MessageType::epoch, "epoch", epoch_fields, epoch_fields},
    {MessageType::version, "version", version_fields, version_fields},
    {MessageType::owner_state, "owner_state", owner_state_fields, owner_state_fields},
    {MessageType::sdo_result, "sdo_result", sdo_result_fields, sdo_result_fields},
    {MessageType::graph, "graph", graph_fields, graph_fields},
    {MessageType::slave_info, "slave_info", slave_info_fields, slave_info_fields},
    {MessageType::sii, "sii", sii_fields, sii_fields},
    {MessageType::reg_result, "reg_result", reg_result_fields, reg_result_fields},
    {MessageType::sdo_info_result, "sdo_info_result", sdo_info_result_fields, sdo_info_result_fields},
    {MessageType::states_result, "states_result", states_result_fields, states_result_fields},
    {MessageType::rescan_result, "rescan_result", rescan_result_fields, rescan_result_fields},
};

const Layout* layout_of(std::uint8_t type) noexcept {
  const Layout* l = std::find_if(std::begin(kLayouts), std::end(kLayouts),
                                 [type](const Layout& x) { return static_cast<std::uint8_t>(x.type) == type; });
  return l != std::end(kLayouts) ? l : nullptr;
}

}  // namespace

const char* to_string(MessageType type) noexcept {
  const Layout* l = layout_of(static_cast<std::uint8_t>(type));
  return l != nullptr ? l->name : "?";
}

bool is_known(std::uint8_t type) noexcept { return layout_of(type) != nullptr; }

bool is_query(MessageType type) noexcept {
  const auto t = static_cast<std::uint8_t>(type);
  return (t >= 0x01 && t <= 0x05) || (t >= 0x07 && t <= 0x0B);  // get_epoch (0x06) is answered before any query
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
  FrameView f;
  DecodeFields fields(datagram.first(kHeaderSize), "reserved header bytes not zero");
  header_fields(fields, f.header);
  RESCUE_TRY(fields.status());
  if (datagram.size() != kHeaderSize + f.header.payload_length + kTagSize) {
    return malformed("datagram length differs from header + payload + tag", datagram.size(), f.header.payload_length);
  }
  f.signed_bytes = datagram.subspan(0, kHeaderSize + f.header.payload_length);
  f.payload = datagram.subspan(kHeaderSize, f.header.payload_length);
  f.tag = datagram.subspan(kHeaderSize + f.header.payload_length, kTagSize);
  return f;
}

Result<Message> decode_payload(const Header& header, ConstByteSpan payload) noexcept {
  const Layout* layout = layout_of(static_cast<std::uint8_t>(header.type));
  if (layout == nullptr) return make_error(Errc::unsupported, "unknown message type", static_cast<std::uint8_t>(header.type));
  Message m;
  m.header = header;
  DecodeFields fields(payload);
  layout->decode(fields, m);
  RESCUE_TRY(fields.status());
  return m;
}

void encode_header(const Header& h, std::uint8_t* out) noexcept {
  EncodeFields fields(ByteSpan(out, kHeaderSize));
  header_fields(fields, h);
}

Result<std::size_t> encode_payload(const Message& m, ByteSpan out) noexcept {
  const Layout* layout = layout_of(static_cast<std::uint8_t>(m.header.type));
  if (layout == nullptr) {
    return make_error(Errc::unsupported, "unknown message type", static_cast<std::uint8_t>(m.header.type));
  }
  EncodeFields fields(out);
  layout->encode(fields, m);
  if (!fields.ok()) return make_error(Errc::capacity_exceeded, "payload buffer too small");
  return fields.size();
}

}  // namespace rescue::app::protocol
