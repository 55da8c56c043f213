// The UDP protocol's codec and tag (docs/protocol.md): every message type round-trips, and every
// rejection reason is produced by the datagram that should produce it; a wrong key never verifies.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <string>
#include <vector>
#include <limits>

#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/protocol_codec.hpp"

namespace rescue::app::protocol {
namespace {

Key key_of(std::uint8_t seed) {
  Key k{};
  for (std::size_t i = 0; i < k.size(); ++i) k[i] = static_cast<std::uint8_t>(seed + i);
  return k;
}

struct Sealed {
  std::array<std::uint8_t, kMaxDatagram + 64> bytes{};
  std::size_t size{0};
};

Sealed seal_ok(const Message& m, const Key& k) {
  Sealed s;
  const Result<std::size_t> n = seal(m, k, ByteSpan(s.bytes.data(), kMaxDatagram));
  EXPECT_TRUE(n.ok());
  s.size = n.ok() ? n.value() : 0;
  return s;
}

// A message for robot 3 in epoch 0x1122334455667788, as a station that asked the epoch sends it.
constexpr std::uint32_t kRobot = 3;
constexpr std::uint64_t kEpoch = 0x1122334455667788ULL;
Message addressed() {
  Message m;
  m.header.robot = kRobot;
  m.header.epoch = kEpoch;
  return m;
}

// Parse, verify and decode like the socket handler; the rejection or nothing.
int judge(const Sealed& s, const Key& k, Message* out = nullptr) {
  const Result<FrameView> f = parse_frame(ConstByteSpan(s.bytes.data(), s.size));
  if (!f.ok()) return static_cast<int>(rejection_of(f.error()));
  if (!verify_frame(f.value(), k).ok()) return static_cast<int>(Rejection::unauthenticated);
  const Result<Message> m = decode_payload(f.value().header, f.value().payload);
  if (!m.ok()) return static_cast<int>(rejection_of(m.error()));
  if (out != nullptr) *out = m.value();
  return -1;
}

TEST(ProtocolCodec, EveryTypeRoundTrips) {
  ASSERT_TRUE(init_crypto().ok());
  const Key k = key_of(1);
  Message m = addressed();
  m.header.sender = 7;
  m.header.sequence = 0x0102030405060708ULL;
  for (const MessageType t : {MessageType::get_status, MessageType::get_slaves, MessageType::get_master, MessageType::get_tasks}) {
    m.header.type = t;
    Message back;
    EXPECT_EQ(judge(seal_ok(m, k), k, &back), -1);
    EXPECT_EQ(back.header.type, t);
    EXPECT_EQ(back.header.sequence, m.header.sequence);
    EXPECT_EQ(back.header.sender, 7U);
    EXPECT_EQ(back.header.robot, kRobot);
    EXPECT_EQ(back.header.epoch, kEpoch);
  }
  m.header.type = MessageType::select_mode;
  m.joints.joints = joint_bit(6) | joint_bit(2);
  m.joints.mode = ControlMode::cyclic_velocity;
  Message back;
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.joints.joints, m.joints.joints);
  EXPECT_EQ(back.joints.mode, ControlMode::cyclic_velocity);
  m.header.type = MessageType::clear_moved;  // ctl clear JOINTS --moved: a joint mask, like clear_joints
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.header.type, MessageType::clear_moved);
  EXPECT_EQ(back.joints.joints, m.joints.joints);
  EXPECT_TRUE(is_control_request(MessageType::clear_moved));
  EXPECT_FALSE(is_query(MessageType::clear_moved));

  m.header.type = MessageType::move_effector;
  m.move.task = 2;
  m.move.effector = Effector::right_hand;
  m.move.position_m = {{0.5, -0.25, 1.0}};
  m.move.rpy_rad = {{0.1, -3.0, 3.0}};
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.move.task, 2);
  EXPECT_EQ(back.move.effector, Effector::right_hand);
  EXPECT_EQ(back.move.position_m, m.move.position_m);
  EXPECT_EQ(back.move.rpy_rad, m.move.rpy_rad);

  m.header.type = MessageType::imu;
  m.imu = ImuRecord{};
  m.imu.time_unix_ns = 123;
  m.imu.orientation_wxyz = {{0.5, 0.5, 0.5, 0.5}};
  m.imu.angular_velocity_rad_s = {{0.1, 0.2, -0.3}};
  m.imu.linear_acceleration_m_s2 = {{0.0, 0.0, 9.81}};
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.imu.orientation_wxyz, m.imu.orientation_wxyz);
  EXPECT_EQ(back.imu.linear_acceleration_m_s2, m.imu.linear_acceleration_m_s2);

  m.header.type = MessageType::gps;
  m.gps = GpsRecord{};
  m.gps.latitude_deg = 35.7;
  m.gps.longitude_deg = 139.7;
  m.gps.altitude_m = 40.0;
  m.gps.horizontal_accuracy_m = 1.5;
  m.gps.fix = GpsFix::rtk;
  m.gps.satellites = 14;
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.gps.latitude_deg, 35.7);
  EXPECT_EQ(back.gps.fix, GpsFix::rtk);
  EXPECT_EQ(back.gps.satellites, 14);

  m.header.type = MessageType::reply;
  m.reply.request_sequence = 99;
  m.reply.request_type = MessageType::enable;
  m.reply.outcome = Outcome::refused;
  m.reply.reason = RefusalReason::state_machine;
  m.reply.refused_joints = joint_bit(3);
  set_text(m.reply.text, "l_shoulder_pitch: enable in Idle");
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_STREQ(back.reply.text.data(), "l_shoulder_pitch: enable in Idle");
  EXPECT_EQ(back.reply.reason, RefusalReason::state_machine);

  m.header.type = MessageType::status;
  m.status.cycle = 5;
  m.status.joints[20].state = 3;
  m.status.joints[20].velocity_rad_s = -1.25;
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.status.joints[20].velocity_rad_s, -1.25);

  m.header.type = MessageType::slaves;
  m.slaves.count = 23;
  set_text(m.slaves.slaves[22].name, "r_shoulder_pitch");
  m.slaves.slaves[22].recovery = 5;  // Mailbox
  m.slaves.slaves[22].recovery_age_ms = 1234;
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_STREQ(back.slaves.slaves[22].name.data(), "r_shoulder_pitch");
  EXPECT_EQ(back.slaves.slaves[22].recovery, 5U);
  EXPECT_EQ(back.slaves.slaves[22].recovery_age_ms, 1234U);
  EXPECT_EQ(back.slaves.slaves[21].recovery_age_ms, kRecoveryAgeNever);
  m.slaves.slaves[22].recovery = kRecoveryStates;  // no such state: the answer is refused
  EXPECT_NE(judge(seal_ok(m, k), k, &back), -1);
  m.slaves.slaves[22].recovery = 0;

  m.header.type = MessageType::tasks;
  m.tasks.count = 2;
  m.tasks.tasks[1].max_execution_ns = 77;
  m.tasks.tasks[1].execution = TimingFigures{1, 2, 3, 4, 5, 6, 7};
  m.tasks.tasks[1].latency = TimingFigures{8, 9, 10, 11, 12, 13, 0xFFFFFFFFU};
  m.tasks.age = FiguresAge{true, 4321};  // the figures' age travels in the list head (issue 36)
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_TRUE(back.tasks.age.stale);
  EXPECT_EQ(back.tasks.age.age_ms, 4321U);
  EXPECT_EQ(back.tasks.tasks[1].max_execution_ns, 77U);
  EXPECT_EQ(back.tasks.tasks[1].execution.min, 1U);
  EXPECT_EQ(back.tasks.tasks[1].execution.p9999, 7U);
  EXPECT_EQ(back.tasks.tasks[1].latency.min, 8U);
  EXPECT_EQ(back.tasks.tasks[1].latency.p999, 13U);
  EXPECT_EQ(back.tasks.tasks[1].latency.p9999, 0xFFFFFFFFU);
  m.tasks.drop_count = 3;  // the queues' drop counters follow the task records
  m.tasks.dropped[0] = 5;
  m.tasks.dropped[2] = 0x0102030405060708ULL;
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.tasks.drop_count, 3U);
  EXPECT_EQ(back.tasks.dropped[0], 5U);
  EXPECT_EQ(back.tasks.dropped[1], 0U);
  EXPECT_EQ(back.tasks.dropped[2], 0x0102030405060708ULL);
  m.tasks.count = kMaxTasks;  // the largest tasks answer (every task, every drop counter) still fits one datagram
  m.tasks.drop_count = kMaxDropCounters;
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.tasks.count, kMaxTasks);
  EXPECT_EQ(back.tasks.drop_count, kMaxDropCounters);

  m.header.type = MessageType::owner_state;  // ctl owner: the figures' age after the owner byte
  m.owner_state.owner = 1;
  m.owner_state.age = FiguresAge{false, 12};
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.owner_state.owner, 1U);
  EXPECT_FALSE(back.owner_state.age.stale);
  EXPECT_EQ(back.owner_state.age.age_ms, 12U);
}

// ctl diag's answer (get_diag/diag): the largest answer (23 slaves) fits one datagram and every
// field comes back; a wrong length, a count above 23, reserved bytes or warning bits outside the 4
// ports are each rejected under their reason.
TEST(ProtocolCodec, DiagRoundTripsAndMalformedDiagIsRejected) {
  ASSERT_TRUE(init_crypto().ok());
  const Key k = key_of(1);
  Message m = addressed();
  m.header.sender = 7;
  m.header.type = MessageType::get_diag;
  Message back;
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.header.type, MessageType::get_diag);
  EXPECT_TRUE(is_query(MessageType::get_diag));
  EXPECT_TRUE(is_control_request(MessageType::get_diag));

  m.header.type = MessageType::diag;
  m.diag.cycle = 0x1122334455667788ULL;
  m.diag.sweeps = 42;
  m.diag.count = static_cast<std::uint8_t>(kMaxSlaves);
  m.diag.slaves[19].ports[0] = DiagPortRecord{5, 1, 0, 2};
  m.diag.slaves[22].ports[3] = DiagPortRecord{0xFFFF, 0xFFFE, 0xFFFD, 0xFFFC};
  m.diag.slaves[19].warned = 0x01;
  m.diag.slaves[19].warned_before = 0x09;
  m.diag.slaves[22].processing_unit_errors = 3;
  m.diag.slaves[22].pdi_errors = 4;
  m.diag.slaves[22].reads = 65535;
  m.diag.age_ms = 77;
  m.diag.stale = 1;
  const Sealed good = seal_ok(m, k);
  EXPECT_EQ(good.size, kHeaderSize + 24 + kMaxSlaves * 40 + kTagSize);
  ASSERT_EQ(judge(good, k, &back), -1);
  EXPECT_EQ(back.diag.cycle, m.diag.cycle);
  EXPECT_EQ(back.diag.sweeps, 42U);
  EXPECT_EQ(back.diag.age_ms, 77U);
  EXPECT_EQ(back.diag.stale, 1U);
  EXPECT_EQ(back.diag.count, kMaxSlaves);
  EXPECT_EQ(back.diag.slaves[19].ports[0].invalid_frames, 5U);
  EXPECT_EQ(back.diag.slaves[19].ports[0].rx_errors, 1U);
  EXPECT_EQ(back.diag.slaves[19].ports[0].lost_links, 2U);
  EXPECT_EQ(back.diag.slaves[22].ports[3].invalid_frames, 0xFFFFU);
  EXPECT_EQ(back.diag.slaves[22].ports[3].rx_errors, 0xFFFEU);
  EXPECT_EQ(back.diag.slaves[22].ports[3].forwarded_errors, 0xFFFDU);
  EXPECT_EQ(back.diag.slaves[22].ports[3].lost_links, 0xFFFCU);
  EXPECT_EQ(back.diag.slaves[19].warned, 0x01);
  EXPECT_EQ(back.diag.slaves[19].warned_before, 0x09);
  EXPECT_EQ(back.diag.slaves[22].processing_unit_errors, 3U);
  EXPECT_EQ(back.diag.slaves[22].pdi_errors, 4U);
  EXPECT_EQ(back.diag.slaves[22].reads, 65535U);

  // The payload alone, decoded with lengths and fields tampered (the tag is not the point here).
  std::array<std::uint8_t, kMaxPayload> payload{};
  const Result<std::size_t> n = encode_payload(m, ByteSpan(payload));
  ASSERT_TRUE(n.ok());
  Header h;
  h.type = MessageType::diag;
  const auto decode = [&](std::size_t length) { return decode_payload(h, ConstByteSpan(payload.data(), length)); };
  ASSERT_TRUE(decode(n.value()).ok());
  for (const std::size_t length : {std::size_t{0}, std::size_t{23}, std::size_t{24}, n.value() - 1}) {
    const Result<Message> bad = decode(length);
    ASSERT_FALSE(bad.ok()) << length;
    EXPECT_EQ(rejection_of(bad.error()), Rejection::malformed) << length;
  }
  payload[0] = static_cast<std::uint8_t>(kMaxSlaves + 1);  // more slaves than the protocol holds
  ASSERT_FALSE(decode(n.value()).ok());
  EXPECT_EQ(rejection_of(decode(n.value()).error()), Rejection::out_of_range);
  payload[0] = static_cast<std::uint8_t>(kMaxSlaves);
  payload[3] = 1;  // reserved
  EXPECT_EQ(rejection_of(decode(n.value()).error()), Rejection::malformed);
  payload[3] = 0;
  payload[24 + 19 * 40 + 38] = 0x10;  // warned: a fifth port
  EXPECT_EQ(rejection_of(decode(n.value()).error()), Rejection::out_of_range);
  payload[24 + 19 * 40 + 38] = 0x01;
  payload[24 + 19 * 40 + 39] = 0x80;  // warned_before: an eighth port
  EXPECT_EQ(rejection_of(decode(n.value()).error()), Rejection::out_of_range);
  payload[24 + 19 * 40 + 39] = 0x09;
  EXPECT_TRUE(decode(n.value()).ok());
  // A get_diag carries no payload.
  h.type = MessageType::get_diag;
  EXPECT_EQ(rejection_of(decode(1).error()), Rejection::malformed);
}

// ctl graph, ctl slaves -v and ctl diag --reset (get_graph/graph, get_slave_info/slave_info,
// diag_reset): the largest answers (23 slaves) fit one datagram and every field comes back; values
// outside their ranges, wrong lengths and reserved bytes are rejected under their reason.
TEST(ProtocolCodec, GraphSlaveInfoAndDiagResetRoundTripAndBadOnesAreRejected) {
  ASSERT_TRUE(init_crypto().ok());
  const Key k = key_of(1);
  Message m = addressed();
  m.header.sender = 7;
  Message back;
  for (const MessageType t : {MessageType::get_graph, MessageType::get_slave_info}) {
    m.header.type = t;
    ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
    EXPECT_EQ(back.header.type, t);
    EXPECT_TRUE(is_query(t));
    EXPECT_TRUE(is_control_request(t));
  }
  EXPECT_EQ(static_cast<int>(MessageType::get_graph), 0x09);
  EXPECT_EQ(static_cast<int>(MessageType::graph), 0x89);
  EXPECT_EQ(static_cast<int>(MessageType::get_slave_info), 0x0A);
  EXPECT_EQ(static_cast<int>(MessageType::slave_info), 0x8A);
  EXPECT_EQ(static_cast<int>(MessageType::diag_reset), 0x17);

  m.header.type = MessageType::diag_reset;
  m.diag_reset.slaves = 1U << 19;
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.diag_reset.slaves, 1U << 19);
  EXPECT_TRUE(is_control_request(MessageType::diag_reset));
  EXPECT_FALSE(is_query(MessageType::diag_reset));
  m.diag_reset.slaves = 0;  // no slave
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  m.diag_reset.slaves = 1U << kMaxSlaves;  // a 24th slave
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));

  m.header.type = MessageType::slave_info;
  m.slave_info.count = static_cast<std::uint8_t>(kMaxSlaves);
  m.slave_info.age = FiguresAge{true, 1234};
  SlaveInfoRecord& elbow = m.slave_info.slaves[19];
  elbow = SlaveInfoRecord{19, 0x1013, 0x00000a5c, 0x4a443432, 0x00010000, 0x52460013, 0x0014, 0x001B,
                          kSlaveInfoIdentity | kSlaveInfoAlRead};
  Sealed good = seal_ok(m, k);
  EXPECT_EQ(good.size, kHeaderSize + 8 + kMaxSlaves * 28 + kTagSize);
  ASSERT_EQ(judge(good, k, &back), -1);
  EXPECT_EQ(back.slave_info.count, kMaxSlaves);
  EXPECT_TRUE(back.slave_info.age.stale);
  EXPECT_EQ(back.slave_info.age.age_ms, 1234U);
  const SlaveInfoRecord& e = back.slave_info.slaves[19];
  EXPECT_EQ(e.position, 19U);
  EXPECT_EQ(e.station, 0x1013U);
  EXPECT_EQ(e.vendor_id, 0x00000a5cU);
  EXPECT_EQ(e.product_code, 0x4a443432U);
  EXPECT_EQ(e.revision, 0x00010000U);
  EXPECT_EQ(e.serial_number, 0x52460013U);
  EXPECT_EQ(e.al_status, 0x0014U);
  EXPECT_EQ(e.al_status_code, 0x001BU);
  EXPECT_EQ(e.flags, kSlaveInfoIdentity | kSlaveInfoAlRead);
  elbow.flags = 0x04;  // no such flag
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  elbow.flags = kSlaveInfoIdentity;
  elbow.position = static_cast<std::uint16_t>(kMaxSlaves);
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  elbow.position = 19;

  m.header.type = MessageType::graph;
  m.graph.count = static_cast<std::uint8_t>(kMaxSlaves);
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    m.graph.slaves[p].position = static_cast<std::uint8_t>(p);
    m.graph.slaves[p].upstream = p == 0 ? kGraphNone : static_cast<std::uint8_t>(p - 1);
  }
  GraphRecord& g = m.graph.slaves[19];
  g = GraphRecord{19, 18, 1, 1, 0x1013, 6, 1, 0, kSlaveLost, 3};
  m.graph.ring = GraphRing{kRingStateOpen, 18, 19, 22, 1, 7, 3, 2};  // the ring, open at the cable into 19
  good = seal_ok(m, k);
  EXPECT_EQ(good.size, kHeaderSize + 8 + kMaxSlaves * 12 + 12 + kTagSize);
  ASSERT_EQ(judge(good, k, &back), -1);
  const GraphRecord& b = back.graph.slaves[19];
  EXPECT_EQ(b.upstream, 18U);
  EXPECT_EQ(b.upstream_port, 1U);
  EXPECT_EQ(b.kind, 1U);
  EXPECT_EQ(b.station, 0x1013U);
  EXPECT_EQ(b.joint, 6U);
  EXPECT_EQ(b.branch, 1U);
  EXPECT_EQ(b.flags, kSlaveLost);
  EXPECT_EQ(b.recovery, 3U);
  EXPECT_EQ(back.graph.slaves[0].upstream, kGraphNone);
  const GraphRing& ring = back.graph.ring;
  EXPECT_EQ(ring.state, kRingStateOpen);
  EXPECT_EQ(ring.before, 18U);
  EXPECT_EQ(ring.after, 19U);
  EXPECT_EQ(ring.return_slave, 22U);
  EXPECT_EQ(ring.return_port, 1U);
  EXPECT_EQ(ring.transients, 7U);
  EXPECT_EQ(ring.breaks, 3U);
  EXPECT_EQ(ring.repairs, 2U);
  m.graph.ring.state = kRingStateLost + 1;
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  m.graph.ring.state = kRingStateOpen;
  m.graph.ring.after = static_cast<std::uint8_t>(kMaxSlaves);  // neither a slave nor a master port
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  m.graph.ring.after = kRingRingPort;
  m.graph.ring.return_port = 4;
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  m.graph.ring.return_port = 1;
  g.upstream = 19;  // a slave downstream of itself: not a tree
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  g.upstream = 18;
  g.upstream_port = 4;  // a fifth port
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  g.upstream_port = 1;
  g.joint = static_cast<std::uint8_t>(kJointCount);
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  g.joint = 6;
  g.recovery = kRecoveryStates;
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  g.recovery = 3;

  // Lengths and reserved bytes, on the payload alone.
  std::array<std::uint8_t, kMaxPayload> payload{};
  const Result<std::size_t> n = encode_payload(m, ByteSpan(payload));
  ASSERT_TRUE(n.ok());
  Header h;
  h.type = MessageType::graph;
  const auto decode = [&](std::size_t length) { return decode_payload(h, ConstByteSpan(payload.data(), length)); };
  ASSERT_TRUE(decode(n.value()).ok());
  for (const std::size_t length : {std::size_t{0}, std::size_t{7}, std::size_t{8}, n.value() - 1}) {
    ASSERT_FALSE(decode(length).ok()) << length;
    EXPECT_EQ(rejection_of(decode(length).error()), Rejection::malformed) << length;
  }
  payload[8 + 19 * 12 + 11] = 1;  // the record's reserved byte
  EXPECT_EQ(rejection_of(decode(n.value()).error()), Rejection::malformed);
  payload[8 + 19 * 12 + 11] = 0;
  payload[8 + kMaxSlaves * 12 + 10] = 1;  // the ring's reserved bytes
  EXPECT_EQ(rejection_of(decode(n.value()).error()), Rejection::malformed);
  h.type = MessageType::get_graph;  // no payload
  EXPECT_EQ(rejection_of(decode(1).error()), Rejection::malformed);
}

TEST(ProtocolCodec, EachRejectionReason) {
  ASSERT_TRUE(init_crypto().ok());
  const Key k = key_of(1);
  Message m = addressed();
  m.header.type = MessageType::enable;
  m.joints.joints = kAllJoints;
  const Sealed good = seal_ok(m, k);
  ASSERT_EQ(judge(good, k), -1);

  Sealed s = good;
  s.size = 10;
  EXPECT_EQ(judge(s, k), static_cast<int>(Rejection::malformed)) << "short";
  s = good;
  s.bytes[0] = 'X';
  EXPECT_EQ(judge(s, k), static_cast<int>(Rejection::malformed)) << "magic";
  s = good;
  s.bytes[4] = 1;
  EXPECT_EQ(judge(s, k), static_cast<int>(Rejection::malformed)) << "version 1 (no robot id, no epoch)";
  s = good;
  s.size -= 1;
  EXPECT_EQ(judge(s, k), static_cast<int>(Rejection::malformed)) << "length";
  s = good;
  s.size = kMaxDatagram + 1;
  EXPECT_EQ(judge(s, k), static_cast<int>(Rejection::oversized));
  s = good;
  s.bytes[32] = 0xFF;
  s.bytes[33] = 0xFF;
  EXPECT_EQ(judge(s, k), static_cast<int>(Rejection::oversized)) << "payload length";
  s = good;
  s.bytes[s.size - 1] ^= 1U;
  EXPECT_EQ(judge(s, k), static_cast<int>(Rejection::unauthenticated)) << "tag";
  EXPECT_EQ(judge(good, key_of(2)), static_cast<int>(Rejection::unauthenticated)) << "wrong key";

  Message bad = m;
  bad.joints.joints = kAllJoints + 1;
  EXPECT_EQ(judge(seal_ok(bad, k), k), static_cast<int>(Rejection::out_of_range)) << "joint mask";
  bad = m;
  bad.header.type = MessageType::move_effector;
  bad.move.position_m[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(judge(seal_ok(bad, k), k), static_cast<int>(Rejection::out_of_range)) << "NaN";
  bad.move.position_m[0] = 5.0;
  EXPECT_EQ(judge(seal_ok(bad, k), k), static_cast<int>(Rejection::out_of_range)) << "reach";
  bad = m;
  bad.header.type = MessageType::select_mode;
  bad.joints.mode = ControlMode::none;
  EXPECT_EQ(judge(seal_ok(bad, k), k), static_cast<int>(Rejection::out_of_range)) << "mode";

  // An unknown type: the structure is fine, the payload decoder does not know it.
  s = good;
  s.bytes[5] = 0x7E;
  const Result<FrameView> f = parse_frame(ConstByteSpan(s.bytes.data(), s.size));
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(static_cast<int>(rejection_of(decode_payload(f.value().header, f.value().payload).error())),
            static_cast<int>(Rejection::unknown_type));
}

// The header of version 2 (docs/protocol.md "Datagram"): the robot id and the epoch sit at their
// offsets, little-endian, inside the authenticated bytes; only get_epoch may leave the epoch 0 (and
// name no robot); the robot's epoch answer echoes the request's sequence; reserved bytes are 0.
TEST(ProtocolCodec, TheRobotIdAndTheEpochAreAuthenticatedHeaderFields) {
  ASSERT_TRUE(init_crypto().ok());
  const Key k = key_of(1);
  Message m = addressed();
  m.header.type = MessageType::get_status;
  m.header.sender = 0x0A0B0C0D;
  m.header.sequence = 0x0102030405060708ULL;
  const Sealed good = seal_ok(m, k);
  ASSERT_EQ(good.size, kHeaderSize + kTagSize);
  EXPECT_EQ(kHeaderSize, 40U);
  EXPECT_EQ(good.bytes[4], 2) << "version 2";
  EXPECT_EQ(good.bytes[8], 0x0D);
  EXPECT_EQ(good.bytes[12], kRobot);
  EXPECT_EQ(good.bytes[16], 0x88);
  EXPECT_EQ(good.bytes[23], 0x11);
  EXPECT_EQ(good.bytes[24], 0x08);
  EXPECT_EQ(good.bytes[32], 0) << "payload length";
  // Changing the robot id or the epoch breaks the tag: they are authenticated.
  for (const std::size_t at : {std::size_t{12}, std::size_t{16}, std::size_t{23}}) {
    Sealed s = good;
    s.bytes[at] ^= 0x40;
    EXPECT_EQ(judge(s, k), static_cast<int>(Rejection::unauthenticated)) << at;
  }
  for (std::size_t at = 34; at < kHeaderSize; ++at) {
    Sealed s = good;
    s.bytes[at] = 1;
    EXPECT_EQ(judge(s, k), static_cast<int>(Rejection::malformed)) << "reserved byte " << at;
  }
  // No robot id, or no epoch, outside get_epoch: malformed.
  Message bad = m;
  bad.header.robot = kAnyRobot;
  EXPECT_EQ(judge(seal_ok(bad, k), k), static_cast<int>(Rejection::malformed));
  bad = m;
  bad.header.epoch = 0;
  EXPECT_EQ(judge(seal_ok(bad, k), k), static_cast<int>(Rejection::malformed));
  // get_epoch: epoch 0, any robot; one with an epoch is malformed.
  Message ask;
  ask.header.type = MessageType::get_epoch;
  ask.header.sender = 4;
  ask.header.sequence = 99;
  Message back;
  EXPECT_EQ(judge(seal_ok(ask, k), k, &back), -1);
  EXPECT_EQ(back.header.type, MessageType::get_epoch);
  EXPECT_TRUE(is_control_request(MessageType::get_epoch));
  ask.header.epoch = kEpoch;
  EXPECT_EQ(judge(seal_ok(ask, k), k), static_cast<int>(Rejection::malformed));
  // The answer: the robot's epoch and id in its header, the request's sequence echoed.
  Message answer = addressed();
  answer.header.type = MessageType::epoch;
  answer.epoch.request_sequence = 99;
  ASSERT_EQ(judge(seal_ok(answer, k), k, &back), -1);
  EXPECT_EQ(back.epoch.request_sequence, 99U);
  EXPECT_EQ(back.header.epoch, kEpoch);
  EXPECT_EQ(back.header.robot, kRobot);
}

}  // namespace
}  // namespace rescue::app::protocol

namespace rescue::app::protocol {
namespace {

// Each seed of the protocol decoder's fuzz target (tests/fuzz/seeds-fuzz_protocol_decoder/NAME: first
// byte the type, then the payload) decodes.
void expect_seeds_decode(std::initializer_list<const char*> seeds) {
  for (const char* seed : seeds) {
    std::ifstream in(std::string(RESCUE_SOURCE_DIR) + "/tests/fuzz/seeds-fuzz_protocol_decoder/" + seed, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(bytes.size(), 1U) << seed;
    Header h;
    h.type = static_cast<MessageType>(static_cast<std::uint8_t>(bytes[0]));
    const Result<Message> decoded =
        decode_payload(h, ConstByteSpan(reinterpret_cast<const std::uint8_t*>(bytes.data()) + 1, bytes.size() - 1));
    EXPECT_TRUE(decoded.ok()) << seed << ": " << (decoded.ok() ? "" : decoded.error().what);
  }
}

// ctl upload/download (0x18, 0x19) and their answer (0x8B): round trips, the ranges, and the fuzz
// target's seeds decode (tests/fuzz/seeds-fuzz_protocol_decoder/sdo_*: first byte the type).
TEST(ProtocolCodec, SdoMessagesRoundTripAndTheirRangesAreChecked) {
  ASSERT_TRUE(init_crypto().ok());
  const Key k = key_of(2);
  Message m = addressed();
  m.header.sender = 9;
  m.header.type = MessageType::sdo_download;
  m.sdo.joint = 5;
  m.sdo.index = 0x2010;
  m.sdo.subindex = 0;
  const char label[] = "harness B7 re-crimped";
  m.sdo.size = sizeof label - 1;
  std::memcpy(m.sdo.data.data(), label, m.sdo.size);
  Message back;
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.sdo.joint, 5);
  EXPECT_EQ(back.sdo.index, 0x2010);
  EXPECT_EQ(back.sdo.size, m.sdo.size);
  EXPECT_EQ(back.sdo.data, m.sdo.data);
  EXPECT_TRUE(is_control_request(MessageType::sdo_download));
  EXPECT_FALSE(is_query(MessageType::sdo_upload));

  m.sdo.size = 0;  // a download of nothing
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  m.sdo.size = 3;  // bytes past the size must be zero
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::malformed));
  m.header.type = MessageType::sdo_upload;
  m.sdo.joint = kJointCount;
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));

  // By slave position (the junctions too): the position travels, the joint stays 0.
  m.sdo.joint = 0;
  m.sdo.target = SdoTarget::slave;
  m.sdo.slave = 1;
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.sdo.target, SdoTarget::slave);
  EXPECT_EQ(back.sdo.slave, 1);
  m.sdo.slave = kMaxSlaves;  // no such position
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  m.sdo.slave = 1;
  m.sdo.joint = 3;  // a joint beside a position: which one?
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  m.sdo.joint = 0;
  m.sdo.target = static_cast<SdoTarget>(kSdoTargetLast + 1);
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  m.sdo.target = SdoTarget::joint;  // a position beside a joint
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));

  Message r = addressed();
  r.header.type = MessageType::sdo_result;
  r.sdo_result.request_sequence = 77;
  r.sdo_result.request_type = MessageType::sdo_upload;
  r.sdo_result.joint = 5;
  r.sdo_result.index = 0x100A;
  r.sdo_result.status = SdoStatus::ok;
  r.sdo_result.flags = kSdoSegmented;
  r.sdo_result.size = 200;
  r.sdo_result.data.fill(0x41);
  set_text(r.sdo_result.text, "done (segmented)");
  ASSERT_EQ(judge(seal_ok(r, k), k, &back), -1);
  EXPECT_EQ(back.sdo_result.request_sequence, 77U);
  EXPECT_EQ(back.sdo_result.size, 200U);
  EXPECT_EQ(back.sdo_result.flags, kSdoSegmented);
  EXPECT_EQ(back.sdo_result.data, r.sdo_result.data);
  EXPECT_STREQ(back.sdo_result.text.data(), "done (segmented)");
  r.sdo_result.status = static_cast<SdoStatus>(kSdoStatusLast + 1);
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::out_of_range));
  r.sdo_result.status = SdoStatus::no_mailbox;
  r.sdo_result.joint = 0;
  r.sdo_result.target = SdoTarget::slave;
  r.sdo_result.slave = 0;  // junction_a
  ASSERT_EQ(judge(seal_ok(r, k), k, &back), -1);
  EXPECT_EQ(back.sdo_result.target, SdoTarget::slave);
  r.sdo_result.slave = kMaxSlaves;
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::out_of_range));

  expect_seeds_decode({"sdo_upload_payload", "sdo_download_payload", "sdo_result_segmented_upload_payload",
                       "sdo_result_refused_payload", "sdo_upload_by_slave_payload", "sdo_result_by_slave_payload"});
}

// ctl sii_read (get_sii 0x0B, sii 0x8C): round trips, the ranges, and the fuzz target's seeds decode.
TEST(ProtocolCodec, SiiMessagesRoundTripAndTheirRangesAreChecked) {
  ASSERT_TRUE(init_crypto().ok());
  const Key k = key_of(2);
  Message m = addressed();
  m.header.sender = 9;
  m.header.type = MessageType::get_sii;
  m.sii_request.slave = 22;
  m.sii_request.offset = 512;
  Message back;
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.sii_request.slave, 22U);
  EXPECT_EQ(back.sii_request.offset, 512U);
  EXPECT_TRUE(is_query(MessageType::get_sii));
  m.sii_request.slave = kMaxSlaves;
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  m.sii_request.slave = 0;
  m.sii_request.offset = kSiiImageBytes;
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));

  Message r = addressed();
  r.header.type = MessageType::sii;
  r.sii.slave = 19;
  r.sii.flags = kSiiRead | kSiiStringsSkipped;
  r.sii.size = 624;
  r.sii.offset = 512;
  r.sii.length = 112;
  for (std::size_t i = 0; i < r.sii.length; ++i) r.sii.bytes[i] = static_cast<std::uint8_t>(i + 1);
  ASSERT_EQ(judge(seal_ok(r, k), k, &back), -1);
  EXPECT_EQ(back.sii.slave, 19U);
  EXPECT_EQ(back.sii.flags, kSiiRead | kSiiStringsSkipped);
  EXPECT_EQ(back.sii.size, 624U);
  EXPECT_EQ(back.sii.offset, 512U);
  EXPECT_EQ(back.sii.bytes, r.sii.bytes);
  r.sii.length = 113;  // past the image's end
  r.sii.bytes[112] = 1;
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::out_of_range));
  r.sii.length = 112;  // a byte past the chunk's length
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::malformed));
  r.sii.bytes[112] = 0;
  r.sii.flags = 0x08;
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::out_of_range));
  r.sii.flags = kSiiRead;
  r.sii.size = kSiiImageBytes + 2;
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::out_of_range));

  expect_seeds_decode({"get_sii_payload", "sii_payload"});
}

// ctl reg_read (reg_read 0x1A, reg_result 0x8D): round trips, every length and range checked, and the
// fuzz target's seeds decode.
TEST(ProtocolCodec, RegisterReadMessagesRoundTripAndTheirRangesAreChecked) {
  ASSERT_TRUE(init_crypto().ok());
  const Key k = key_of(2);
  Message m = addressed();
  m.header.sender = 9;
  m.header.type = MessageType::reg_read;
  m.reg_read.slave = 19;
  m.reg_read.address = 0x0130;
  m.reg_read.length = 2;
  Message back;
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.reg_read.slave, 19);
  EXPECT_EQ(back.reg_read.address, 0x0130);
  EXPECT_EQ(back.reg_read.length, 2);
  EXPECT_TRUE(is_control_request(MessageType::reg_read));
  EXPECT_FALSE(is_query(MessageType::reg_read));
  m.reg_read.length = 0;
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  m.reg_read.length = kRegDataSize + 1;
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  m.reg_read.length = 2;
  m.reg_read.address = 0xFFFF;  // past the register space
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  m.reg_read.address = 0x0130;
  m.reg_read.slave = kMaxSlaves;
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));

  Message r = addressed();
  r.header.type = MessageType::reg_result;
  r.reg_result.request_sequence = 77;
  r.reg_result.slave = 19;
  r.reg_result.address = 0x0130;
  r.reg_result.length = 2;
  r.reg_result.wkc = 1;
  r.reg_result.frames = 1;
  r.reg_result.data[0] = 0x08;
  ASSERT_EQ(judge(seal_ok(r, k), k, &back), -1);
  EXPECT_EQ(back.reg_result.request_sequence, 77U);
  EXPECT_EQ(back.reg_result.data, r.reg_result.data);
  EXPECT_EQ(back.reg_result.wkc, 1);
  r.reg_result.data[2] = 1;  // bytes past the length must be zero
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::malformed));
  r.reg_result.data[2] = 0;
  r.reg_result.status = static_cast<RegStatus>(kRegStatusLast + 1);
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::out_of_range));
  r.reg_result.status = RegStatus::ok;
  r.reg_result.length = kRegDataSize + 1;
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::out_of_range));

  expect_seeds_decode({"reg_read_payload", "reg_result_payload", "reg_result_lost_payload"});
}

// ctl sdos (sdo_info 0x1B, sdo_info_result 0x8E): round trips, every range and length checked (a
// window past the response, bytes past its length), and the fuzz target's seeds decode.
TEST(ProtocolCodec, SdoInformationMessagesRoundTripAndTheirRangesAreChecked) {
  ASSERT_TRUE(init_crypto().ok());
  const Key k = key_of(2);
  Message m = addressed();
  m.header.sender = 9;
  m.header.type = MessageType::sdo_info;
  m.sdo_info.target = SdoTarget::slave;
  m.sdo_info.slave = 13;
  m.sdo_info.op = SdoInfoOp::od_list;
  m.sdo_info.index = 1;
  m.sdo_info.offset = 256;
  Message back;
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.sdo_info.slave, 13);
  EXPECT_EQ(back.sdo_info.op, SdoInfoOp::od_list);
  EXPECT_EQ(back.sdo_info.offset, 256);
  EXPECT_TRUE(is_control_request(MessageType::sdo_info));
  EXPECT_FALSE(is_query(MessageType::sdo_info));
  m.sdo_info.index = 6;  // no such list type
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  m.sdo_info.index = 1;
  m.sdo_info.op = static_cast<SdoInfoOp>(2);  // a response's opcode
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  m.sdo_info.op = SdoInfoOp::object_description;  // an offset belongs to the OD list only
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  m.sdo_info.offset = 0;
  m.sdo_info.subindex = 1;  // and a subindex to an entry
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  m.sdo_info.op = SdoInfoOp::entry_description;
  m.sdo_info.slave = kMaxSlaves;
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));

  Message r = addressed();
  r.header.type = MessageType::sdo_info_result;
  r.sdo_info_result.request_sequence = 77;
  r.sdo_info_result.request.target = SdoTarget::joint;
  r.sdo_info_result.request.joint = 5;
  r.sdo_info_result.request.op = SdoInfoOp::od_list;
  r.sdo_info_result.request.index = 1;
  r.sdo_info_result.request.offset = 2;
  r.sdo_info_result.total = 8;
  r.sdo_info_result.length = 6;
  r.sdo_info_result.exchanges = 4;
  for (std::size_t i = 0; i < 6; ++i) r.sdo_info_result.data[i] = static_cast<std::uint8_t>(i + 1);
  ASSERT_EQ(judge(seal_ok(r, k), k, &back), -1);
  EXPECT_EQ(back.sdo_info_result.request_sequence, 77U);
  EXPECT_EQ(back.sdo_info_result.request.joint, 5);
  EXPECT_EQ(back.sdo_info_result.total, 8);
  EXPECT_EQ(back.sdo_info_result.data, r.sdo_info_result.data);
  r.sdo_info_result.length = 7;  // offset 2 + 7 past the 8 bytes of the response
  r.sdo_info_result.data[6] = 7;
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::out_of_range));
  r.sdo_info_result.length = 6;
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::malformed)) << "a byte past the length";
  r.sdo_info_result.data[6] = 0;
  r.sdo_info_result.length = kSdoDataSize + 1;
  r.sdo_info_result.total = 0xFFFF;
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::out_of_range));
  r.sdo_info_result.length = 6;
  r.sdo_info_result.status = static_cast<SdoStatus>(kSdoStatusLast + 1);
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::out_of_range));

  expect_seeds_decode({"sdo_info_od_list_by_slave_payload", "sdo_info_entry_payload", "sdo_info_result_od_list_payload",
                       "sdo_info_result_no_mailbox_payload"});
}

// ctl states (0x1C) and its answer (0x8F): round trips, every range, a record of a slave outside
// the request, a payload one byte short, and the fuzz target's seeds decode.
TEST(ProtocolCodec, StatesMessagesRoundTripAndTheirRangesAreChecked) {
  ASSERT_TRUE(init_crypto().ok());
  const Key k = key_of(2);
  Message m = addressed();
  m.header.sender = 9;
  m.header.type = MessageType::states;
  m.states.slaves = 1U << 19;
  m.states.state = 2;
  Message back;
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.states.slaves, 1U << 19);
  EXPECT_EQ(back.states.state, 2);
  EXPECT_TRUE(is_control_request(MessageType::states));
  EXPECT_FALSE(is_query(MessageType::states));
  m.states.state = 3;  // BOOT: not asked for
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  m.states.state = 8;
  m.states.slaves = 0;
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));
  m.states.slaves = 1U << kMaxSlaves;
  EXPECT_EQ(judge(seal_ok(m, k), k), static_cast<int>(Rejection::out_of_range));

  Message r = addressed();
  r.header.type = MessageType::states_result;
  r.states_result.request_sequence = 77;
  r.states_result.slaves = (1U << 19) | (1U << 20);
  r.states_result.state = 4;
  r.states_result.status = StatesStatus::not_reached;
  r.states_result.frames = 9;
  r.states_result.records[19] = {StateOutcome::reached, 0x0004, 0};
  r.states_result.records[20] = {StateOutcome::refused, 0x0012, 0x0011};
  ASSERT_EQ(judge(seal_ok(r, k), k, &back), -1);
  EXPECT_EQ(back.states_result.request_sequence, 77U);
  EXPECT_EQ(back.states_result.records[20].outcome, StateOutcome::refused);
  EXPECT_EQ(back.states_result.records[20].al_status, 0x0012);
  EXPECT_EQ(back.states_result.records[20].al_code, 0x0011);
  EXPECT_EQ(back.states_result.frames, 9);
  r.states_result.records[3].al_status = 8;  // a slave outside the request
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::malformed));
  r.states_result.records[3].al_status = 0;
  r.states_result.records[19].outcome = static_cast<StateOutcome>(kStateOutcomeLast + 1);
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::out_of_range));
  r.states_result.records[19].outcome = StateOutcome::reached;
  r.states_result.status = static_cast<StatesStatus>(kStatesStatusLast + 1);
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::out_of_range));
  r.states_result.status = StatesStatus::in_service;
  r.states_result.in_service = 1U << kJointCount;  // no such joint
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::out_of_range));

  // A payload one byte short of its type's length is malformed (every length checked).
  std::array<std::uint8_t, kMaxPayload> payload{};
  r.states_result.in_service = 0;
  const Result<std::size_t> n = encode_payload(r, ByteSpan(payload));
  ASSERT_TRUE(n.ok());
  Header h;
  h.type = MessageType::states_result;
  EXPECT_FALSE(decode_payload(h, ConstByteSpan(payload.data(), n.value() - 1)).ok());
  EXPECT_TRUE(decode_payload(h, ConstByteSpan(payload.data(), n.value())).ok());

  expect_seeds_decode({"states_payload", "states_result_payload", "states_result_in_service_payload",
                       "states_result_refused_payload"});
}

// ctl rescan (0x1D) and its answer (0x90): round trips, the counts and positions checked, a record
// past its count refused, a payload one byte short, and the fuzz target's seeds decode.
TEST(ProtocolCodec, RescanMessagesRoundTripAndTheirRangesAreChecked) {
  ASSERT_TRUE(init_crypto().ok());
  const Key k = key_of(2);
  Message m = addressed();
  m.header.sender = 9;
  m.header.type = MessageType::rescan;
  Message back;
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.header.type, MessageType::rescan);
  EXPECT_TRUE(is_control_request(MessageType::rescan));
  EXPECT_FALSE(is_query(MessageType::rescan));

  Message r = addressed();
  r.header.type = MessageType::rescan_result;
  r.rescan_result.request_sequence = 78;
  r.rescan_result.counted = 22;
  r.rescan_result.devices = 2;
  r.rescan_result.frames = 40;
  r.rescan_result.records[0] = {0xA5C, 0x4A423430, 1, 17, 0, 0, 1};
  r.rescan_result.records[1] = {0xA5C, 0x4A443432, 2, 18, 0x0007, 1, 1};
  r.rescan_result.differences = 1;
  r.rescan_result.found_differences[0] = {RescanDifference::missing, 15, kNoPlace};
  ASSERT_EQ(judge(seal_ok(r, k), k, &back), -1);
  EXPECT_EQ(back.rescan_result.request_sequence, 78U);
  EXPECT_EQ(back.rescan_result.records[1].serial_number, 18U);
  EXPECT_EQ(back.rescan_result.records[1].station_alias, 0x0007);
  EXPECT_EQ(back.rescan_result.found_differences[0].planned, 15);
  EXPECT_EQ(back.rescan_result.frames, 40);
  r.rescan_result.records[2].vendor_id = 1;  // past the device count
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::malformed));
  r.rescan_result.records[2].vendor_id = 0;
  r.rescan_result.found_differences[0].found = 2;  // a device not read
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::out_of_range));
  r.rescan_result.found_differences[0].found = kNoPlace;
  r.rescan_result.records[1].slot = kMaxSlaves;
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::out_of_range));
  r.rescan_result.records[1].slot = 1;
  r.rescan_result.devices = kRescanDevices + 1;
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::out_of_range));
  r.rescan_result.devices = 2;
  r.rescan_result.status = static_cast<RescanStatus>(kRescanStatusLast + 1);
  EXPECT_EQ(judge(seal_ok(r, k), k), static_cast<int>(Rejection::out_of_range));
  r.rescan_result.status = RescanStatus::ok;

  std::array<std::uint8_t, kMaxPayload> payload{};
  const Result<std::size_t> n = encode_payload(r, ByteSpan(payload));
  ASSERT_TRUE(n.ok());
  Header h;
  h.type = MessageType::rescan_result;
  EXPECT_FALSE(decode_payload(h, ConstByteSpan(payload.data(), n.value() - 1)).ok());
  EXPECT_TRUE(decode_payload(h, ConstByteSpan(payload.data(), n.value())).ok());

  expect_seeds_decode({"rescan_payload", "rescan_result_payload", "rescan_result_incomplete_payload"});
}

// Text fields hold printable ASCII then NUL padding (docs/protocol.md "Text fields", issue 35 item 4):
// the robot sends any other byte of its own texts as '?', and a receiver refuses a reply whose text
// holds a terminal escape, a byte above 0x7E, or anything after its first NUL.
TEST(ProtocolCodec, TextFieldsHoldOnlyPrintableAsciiThenNulPadding) {
  Message m;
  m.header.type = MessageType::reply;
  m.reply.outcome = Outcome::refused;
  m.reply.reason = RefusalReason::state_machine;
  const char kHostile[] = "x\x1b]0;pwned\x07\xff";
  std::memcpy(m.reply.text.data(), kHostile, sizeof kHostile);
  std::array<std::uint8_t, kMaxPayload> payload{};
  const Result<std::size_t> n = encode_payload(m, ByteSpan(payload));
  ASSERT_TRUE(n.ok());
  Header h;
  h.type = MessageType::reply;
  const auto decode = [&] { return decode_payload(h, ConstByteSpan(payload.data(), n.value())); };
  ASSERT_TRUE(decode().ok()) << decode().error().what;
  EXPECT_STREQ(decode().value().reply.text.data(), "x?]0;pwned??") << "encoded with every other byte as '?'";

  constexpr std::size_t kText = 16;  // the reply's text field (docs/protocol.md: 16:64)
  payload[kText + 1] = 0x1B;  // ESC
  ASSERT_FALSE(decode().ok());
  EXPECT_EQ(rejection_of(decode().error()), Rejection::malformed);
  payload[kText + 1] = 0xC3;  // above 0x7E
  EXPECT_EQ(rejection_of(decode().error()), Rejection::malformed);
  payload[kText + 1] = '?';
  ASSERT_TRUE(decode().ok());
  payload[kText + 40] = 'A';  // after the first NUL
  EXPECT_EQ(rejection_of(decode().error()), Rejection::malformed);
  payload[kText + 40] = 0;
  // A JSON-breaking text of printable ASCII is valid on the wire: ctl escapes it (tested end to end).
  const char kQuotes[] = R"(x","accepted":true,"reason":"none)";
  std::memcpy(payload.data() + kText, kQuotes, sizeof kQuotes);
  EXPECT_TRUE(decode().ok());
}

}  // namespace
}  // namespace rescue::app::protocol
