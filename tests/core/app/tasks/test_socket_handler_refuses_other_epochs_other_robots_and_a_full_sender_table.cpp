// The socket handler's replay protection and robot binding (docs/protocol.md "Replay protection",
// "Senders", docs/security.md): get_epoch is answered with the epoch and robot id in the header and
// the request's sequence echoed, taking no sender slot; a recorded authentic datagram is accepted
// once, and refused (replayed) after a new epoch (a restart) whatever the sender's clock says; a
// datagram naming another robot is refused as wrong_robot; a 17th sender is counted as
// sender_table_full and told so in a refusal reply, never silently.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <string>

#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/protocol_codec.hpp"
#include "core/app/tasks/socket_handler.hpp"
#include "tests/support/authentic_answer.hpp"
#include "tests/support/loopback_socket_handler.hpp"

namespace rescue::app {
namespace {

using protocol::Rejection;

constexpr std::uint64_t kT0 = static_cast<std::uint64_t>(test::LoopbackSocketHandler::kNow);

protocol::Key test_key() {
  protocol::Key k{};
  k.fill(0x3C);
  return k;
}

struct Datagram {
  std::array<std::uint8_t, protocol::kMaxDatagram> bytes{};
  std::size_t size{0};
};

struct Bench : test::LoopbackSocketHandler {
  Bench() : LoopbackSocketHandler(SocketHandlerPorts{}, test_key()) {}
  Datagram sealed(const protocol::Message& m) {
    Datagram d;
    const Result<std::size_t> n = protocol::seal(m, key, ByteSpan(d.bytes));
    EXPECT_TRUE(n.ok());
    d.size = n.ok() ? n.value() : 0;
    return d;
  }
  Datagram get_status(std::uint32_t sender, std::uint64_t sequence) {
    protocol::Message m;
    m.header.type = protocol::MessageType::get_status;
    m.header.sender = sender;
    m.header.sequence = sequence;
    return sealed(for_robot(m));
  }
  void send(const Datagram& d) {
    ASSERT_TRUE(client.send_to(loopback, handler.control_port(), ConstByteSpan(d.bytes.data(), d.size)).ok());
    handler.step(0);
  }
  // The next authentic answer to the client, if any within 200 ms.
  bool answer(protocol::Message& out) { return test::receive_authentic(client, key, 200, out); }
  std::uint64_t rejected(Rejection r) const { return handler.counters().rejected[static_cast<std::size_t>(r)]; }
};

TEST(SocketHandlerEpoch, GetEpochIsAnsweredWithTheEpochAndRobotIdAndTheSequenceEchoed) {
  Bench b;
  protocol::Message ask;
  ask.header.type = protocol::MessageType::get_epoch;
  ask.header.sender = 9;
  ask.header.sequence = 12345;
  b.send(b.sealed(ask));  // robot kAnyRobot, epoch 0
  protocol::Message answer;
  ASSERT_TRUE(b.answer(answer));
  EXPECT_EQ(answer.header.type, protocol::MessageType::epoch);
  EXPECT_EQ(answer.header.epoch, test::LoopbackSocketHandler::kEpoch);
  EXPECT_EQ(answer.header.robot, protocol::kDefaultRobotId);
  EXPECT_EQ(answer.header.sender, kRobotSenderId);
  EXPECT_EQ(answer.epoch.request_sequence, 12345U);
  EXPECT_EQ(b.window.senders(), 0U) << "get_epoch takes no sender slot";
  // Asking a robot by another id: refused as wrong_robot, no answer.
  ask.header.robot = 2;
  b.send(b.sealed(ask));
  EXPECT_FALSE(b.answer(answer));
  EXPECT_EQ(b.rejected(Rejection::wrong_robot), 1U);
}

TEST(SocketHandlerEpoch, ARecordedDatagramIsAcceptedOnceAndRefusedAfterARestartsNewEpoch) {
  Bench b;
  const Datagram recorded = b.get_status(1, kT0);
  b.send(recorded);
  protocol::Message answer;
  ASSERT_TRUE(b.answer(answer));
  EXPECT_EQ(answer.header.type, protocol::MessageType::status);
  EXPECT_EQ(b.handler.counters().accepted, 1U);
  b.send(recorded);
  EXPECT_EQ(b.rejected(Rejection::replayed), 1U);

  // A restart begins a new epoch: nothing is kept on disk, and the recorded datagram (whose sender
  // clock was far ahead, as a sender's clock may be) is refused all the same.
  b.window.begin_epoch(protocol::new_epoch());
  const Datagram from_the_future = [&] {
    protocol::Message m;
    m.header.type = protocol::MessageType::get_status;
    m.header.sender = 1;
    m.header.sequence = kT0 + 3'600'000'000'000ULL;
    m.header.robot = protocol::kDefaultRobotId;
    m.header.epoch = test::LoopbackSocketHandler::kEpoch;  // the old epoch
    return b.sealed(m);
  }();
  b.send(recorded);
  b.send(from_the_future);
  EXPECT_FALSE(b.answer(answer));
  EXPECT_EQ(b.rejected(Rejection::replayed), 3U);
  EXPECT_EQ(b.handler.counters().accepted, 1U);
  // The station asks the new epoch and is served again.
  b.send(b.get_status(1, kT0 + 1));
  ASSERT_TRUE(b.answer(answer));
  EXPECT_EQ(answer.header.epoch, b.window.epoch());
  EXPECT_EQ(b.handler.counters().accepted, 2U);
}

TEST(SocketHandlerEpoch, ADatagramForAnotherRobotIsRefusedAsWrongRobot) {
  Bench b;
  protocol::Message m;
  m.header.type = protocol::MessageType::get_status;
  m.header.sender = 1;
  m.header.sequence = kT0;
  m = b.for_robot(m);
  m.header.robot = 2;
  b.send(b.sealed(m));
  protocol::Message answer;
  EXPECT_FALSE(b.answer(answer));
  EXPECT_EQ(b.rejected(Rejection::wrong_robot), 1U);
  EXPECT_EQ(b.handler.counters().accepted, 0U);
  EXPECT_EQ(b.window.senders(), 0U) << "refused before the replay window";
}

TEST(SocketHandlerEpoch, ASeventeenthSenderIsToldTheTableIsFullAndCountedAsSuch) {
  Bench b;
  protocol::Message answer;
  for (std::uint32_t s = 1; s <= protocol::kMaxSenders; ++s) {
    b.send(b.get_status(s, kT0));
    ASSERT_TRUE(b.answer(answer)) << s;
  }
  b.send(b.get_status(protocol::kMaxSenders + 1, kT0));
  ASSERT_TRUE(b.answer(answer));
  EXPECT_EQ(answer.header.type, protocol::MessageType::reply);
  EXPECT_EQ(answer.reply.outcome, protocol::Outcome::refused);
  EXPECT_EQ(answer.reply.reason, protocol::RefusalReason::sender_table_full);
  EXPECT_EQ(answer.reply.request_sequence, kT0);
  EXPECT_NE(std::string(answer.reply.text.data()).find("restart the robot"), std::string::npos) << answer.reply.text.data();
  EXPECT_EQ(b.rejected(Rejection::sender_table_full), 1U);
  EXPECT_EQ(b.rejected(Rejection::replayed), 0U) << "a full table is not a replay";
  EXPECT_EQ(b.rejected(Rejection::out_of_range), 0U);
}

}  // namespace
}  // namespace rescue::app
