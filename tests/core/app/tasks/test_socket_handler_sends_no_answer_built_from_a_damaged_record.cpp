// Every answer the socket handler sends is built from records of the shared segment (the parser's
// replies, the EtherCAT handler's results, the published figures). A reply whose outcome, reason or
// refused joints no writer writes is damage (a stray write, a bit flip): it is not sent and it is
// counted (SocketHandler::damaged_records); the operator's ctl times out. Before, it was sent as it
// was and ctl's decoder refused the answer. A whole reply after it is sent as before.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>

#include "core/app/links/task_links.hpp"
#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/protocol_codec.hpp"
#include "core/app/tasks/socket_handler.hpp"
#include "core/concurrency/spsc_message_port.hpp"
#include "hal/net/udp_socket.hpp"
#include "tests/support/loopback_socket_handler.hpp"

namespace rescue::app {
namespace {

using protocol::MessageType;

struct Replies {
  SpscQueue<ControlReply, TaskLinks::kReplyQueueDepth> queue;
  SpscMessageSource<ControlReply, TaskLinks::kReplyQueueDepth> source{queue};
  SocketHandlerPorts ports() {
    SocketHandlerPorts p;
    p.replies = &source;
    return p;
  }
};

struct Bench : test::LoopbackSocketHandler {
  explicit Bench(const SocketHandlerPorts& ports) : LoopbackSocketHandler(ports, protocol::Key{}) {}
  // A whole reply to the client's port, as the parser writes it.
  ControlReply reply(std::uint64_t sequence) const {
    ControlReply r;
    r.reply_address = loopback;
    r.reply_port = client.local_port();
    r.sender = 3;
    r.request_sequence = sequence;
    r.request_type = MessageType::get_status;
    r.outcome = protocol::Outcome::accepted;
    return r;
  }
  // Whether a datagram reached the client within 200 ms.
  bool answered() {
    if (!client.wait_readable(200)) return false;
    std::array<hal::UdpDatagram, 1> in{};
    return client.receive_batch(Span<hal::UdpDatagram>(in)) == 1;
  }
};

TEST(SocketHandlerDamagedAnswer, AReplyWithValuesNoWriterWritesIsNotSentAndCounted) {
  ASSERT_TRUE(protocol::init_crypto().ok());
  Replies q;
  Bench b(q.ports());
  ControlReply outcome = b.reply(1);
  const unsigned char seven = 7;
  std::memcpy(&outcome.outcome, &seven, 1);  // neither accepted nor refused
  ControlReply reason = b.reply(2);
  reason.outcome = protocol::Outcome::refused;
  const unsigned char far = 0xC8;
  std::memcpy(&reason.reason, &far, 1);  // no RefusalReason
  ControlReply joints = b.reply(3);
  joints.outcome = protocol::Outcome::refused;
  joints.reason = protocol::RefusalReason::state_machine;
  joints.refused_joints = JointMask{1} << 30;  // beyond the robot
  for (const ControlReply& r : {outcome, reason, joints}) {
    ASSERT_TRUE(q.queue.try_push(r));
    b.handler.step(0);
    EXPECT_FALSE(b.answered()) << r.request_sequence;
  }
  EXPECT_EQ(b.handler.damaged_records(), 3U);
  ASSERT_TRUE(q.queue.try_push(b.reply(4)));
  b.handler.step(1'000'000);
  EXPECT_TRUE(b.answered()) << "a whole reply is sent as before";
  EXPECT_EQ(b.handler.damaged_records(), 3U);
}

}  // namespace
}  // namespace rescue::app
