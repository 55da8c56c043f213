// The socket handler against a key holder who would lock the operator out (docs/protocol.md
// "Senders", docs/security.md (5)): an authentic request whose payload is then refused takes no
// sender slot; a sequence more than 10 min ahead of the robot's clock (2^64-1) is refused with a
// reply saying so, counted out_of_range, and leaves its sender served; other senders can never take
// the operator's (sender 1's) slot.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <string>

#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/protocol_codec.hpp"
#include "core/app/tasks/socket_handler.hpp"
#include "core/robot/robot.hpp"
#include "tests/support/authentic_answer.hpp"
#include "tests/support/loopback_socket_handler.hpp"

namespace rescue::app {
namespace {

using protocol::Rejection;

constexpr std::uint64_t kT0 = static_cast<std::uint64_t>(test::LoopbackSocketHandler::kNow);

struct Rig : test::LoopbackSocketHandler {
  Rig() : LoopbackSocketHandler(SocketHandlerPorts{}, [] {
            protocol::Key k{};
            k.fill(0x5A);
            return k;
          }()) {}
  void send(protocol::Message m) {
    std::array<std::uint8_t, protocol::kMaxDatagram> bytes{};
    const Result<std::size_t> n = protocol::seal(for_robot(m), key, ByteSpan(bytes));
    ASSERT_TRUE(n.ok());
    ASSERT_TRUE(client.send_to(loopback, handler.control_port(), ConstByteSpan(bytes.data(), n.value())).ok());
    handler.step(0);
  }
  void get_status(std::uint32_t sender, std::uint64_t sequence) {
    protocol::Message m;
    m.header.type = protocol::MessageType::get_status;
    m.header.sender = sender;
    m.header.sequence = sequence;
    send(m);
  }
  bool answer(protocol::Message& out) { return test::receive_authentic(client, key, 200, out); }
  std::uint64_t rejected(Rejection r) const { return handler.counters().rejected[static_cast<std::size_t>(r)]; }
};

TEST(SocketHandlerSlots, AnAuthenticButMalformedRequestTakesNoSlot) {
  Rig r;
  for (std::uint32_t s = 2; s < 2 + protocol::kMaxSenders; ++s) {
    protocol::Message m;
    m.header.type = protocol::MessageType::enable;
    m.header.sender = s;
    m.header.sequence = kT0;
    m.joints.joints = kAllJoints + 1;  // no such joint: refused by decode_payload
    r.send(m);
  }
  EXPECT_EQ(r.rejected(Rejection::out_of_range), protocol::kMaxSenders);
  EXPECT_EQ(r.window.senders(), 0U);
  protocol::Message answer;
  EXPECT_FALSE(r.answer(answer)) << "a malformed request is not answered";
  r.get_status(2 + protocol::kMaxSenders, kT0);
  ASSERT_TRUE(r.answer(answer));
  EXPECT_EQ(answer.header.type, protocol::MessageType::status);
  EXPECT_EQ(r.rejected(Rejection::sender_table_full), 0U);
}

TEST(SocketHandlerSlots, ASequenceFarAheadOfTheRobotsClockIsRefusedAndLocksNobodyOut) {
  Rig r;
  r.get_status(1U, UINT64_MAX);
  protocol::Message answer;
  ASSERT_TRUE(r.answer(answer));
  EXPECT_EQ(answer.header.type, protocol::MessageType::reply);
  EXPECT_EQ(answer.reply.outcome, protocol::Outcome::refused);
  EXPECT_EQ(answer.reply.reason, protocol::RefusalReason::bad_request);
  EXPECT_NE(std::string(answer.reply.text.data()).find("ahead of the robot's clock"), std::string::npos)
      << answer.reply.text.data();
  EXPECT_EQ(r.rejected(Rejection::out_of_range), 1U);
  EXPECT_EQ(r.rejected(Rejection::replayed), 0U);
  // The operator's next request, numbered by its own clock, is served.
  r.get_status(1U, kT0);
  ASSERT_TRUE(r.answer(answer));
  EXPECT_EQ(answer.header.type, protocol::MessageType::status);
  EXPECT_EQ(r.handler.counters().accepted, 1U);
}

TEST(SocketHandlerSlots, FifteenOtherSendersLeaveTheOperatorsSlot) {
  Rig r;
  protocol::Message answer;
  for (std::uint32_t s = 2; s < 2 + protocol::kMaxSenders; ++s) {
    r.get_status(s, kT0);
    ASSERT_TRUE(r.answer(answer)) << s;
  }
  EXPECT_EQ(r.rejected(Rejection::sender_table_full), 1U) << "the 16th other sender finds no slot";
  r.get_status(1U, kT0);
  ASSERT_TRUE(r.answer(answer));
  EXPECT_EQ(answer.header.type, protocol::MessageType::status);
  EXPECT_EQ(r.window.senders(), protocol::kMaxSenders);
}

}  // namespace
}  // namespace rescue::app
