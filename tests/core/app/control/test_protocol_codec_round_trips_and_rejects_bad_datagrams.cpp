// The UDP protocol's codec and tag (docs/protocol.md): every message type round-trips, and every
// rejection reason is produced by the datagram that should produce it; a wrong key never verifies.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>

#include "core/app/control/protocol_auth.hpp"
#include "core/app/control/protocol_codec.hpp"

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
  Message m;
  m.header.sender = 7;
  m.header.sequence = 0x0102030405060708ULL;
  for (const MessageType t : {MessageType::get_status, MessageType::get_slaves, MessageType::get_master, MessageType::get_tasks}) {
    m.header.type = t;
    Message back;
    EXPECT_EQ(judge(seal_ok(m, k), k, &back), -1);
    EXPECT_EQ(back.header.type, t);
    EXPECT_EQ(back.header.sequence, m.header.sequence);
    EXPECT_EQ(back.header.sender, 7U);
  }
  m.header.type = MessageType::select_mode;
  m.joints.joints = joint_bit(6) | joint_bit(2);
  m.joints.mode = ControlMode::cyclic_velocity;
  Message back;
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.joints.joints, m.joints.joints);
  EXPECT_EQ(back.joints.mode, ControlMode::cyclic_velocity);

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
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_STREQ(back.slaves.slaves[22].name.data(), "r_shoulder_pitch");

  m.header.type = MessageType::tasks;
  m.tasks.count = 2;
  m.tasks.tasks[1].max_execution_ns = 77;
  m.tasks.tasks[1].execution = TimingFigures{1, 2, 3, 4, 5, 6, 7};
  m.tasks.tasks[1].latency = TimingFigures{8, 9, 10, 11, 12, 13, 0xFFFFFFFFU};
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.tasks.tasks[1].max_execution_ns, 77U);
  EXPECT_EQ(back.tasks.tasks[1].execution.min, 1U);
  EXPECT_EQ(back.tasks.tasks[1].execution.p9999, 7U);
  EXPECT_EQ(back.tasks.tasks[1].latency.min, 8U);
  EXPECT_EQ(back.tasks.tasks[1].latency.p999, 13U);
  EXPECT_EQ(back.tasks.tasks[1].latency.p9999, 0xFFFFFFFFU);
  m.tasks.count = kMaxTasks;  // the largest tasks answer still fits one datagram
  ASSERT_EQ(judge(seal_ok(m, k), k, &back), -1);
  EXPECT_EQ(back.tasks.count, kMaxTasks);
}

TEST(ProtocolCodec, EachRejectionReason) {
  ASSERT_TRUE(init_crypto().ok());
  const Key k = key_of(1);
  Message m;
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
  s.bytes[4] = 2;
  EXPECT_EQ(judge(s, k), static_cast<int>(Rejection::malformed)) << "version";
  s = good;
  s.size -= 1;
  EXPECT_EQ(judge(s, k), static_cast<int>(Rejection::malformed)) << "length";
  s = good;
  s.size = kMaxDatagram + 1;
  EXPECT_EQ(judge(s, k), static_cast<int>(Rejection::oversized));
  s = good;
  s.bytes[20] = 0xFF;
  s.bytes[21] = 0xFF;
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

}  // namespace
}  // namespace rescue::app::protocol
