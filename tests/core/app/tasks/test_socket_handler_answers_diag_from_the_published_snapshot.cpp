// `ctl diag` inside the robot (docs/protocol.md, docs/operator.md): the socket handler answers an
// authentic get_diag with the link-quality snapshot the EtherCAT handler's loop last published
// (TaskLinks::link_diag), field for field; before any snapshot it answers an empty one (cycle 0).
#include <gtest/gtest.h>

#include <array>
#include <cstdint>

#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/protocol_codec.hpp"
#include "core/app/tasks/socket_handler.hpp"
#include "hal/net/udp_socket.hpp"
#include "tests/support/loopback_socket_handler.hpp"

namespace rescue::app {
namespace {

constexpr std::int64_t kNow = test::LoopbackSocketHandler::kNow;

struct Bench : test::LoopbackSocketHandler {
  explicit Bench(const SocketHandlerPorts& ports) : LoopbackSocketHandler(ports, protocol::Key{}) {}
  // Sends get_diag, lets the handler answer, returns the decoded answer.
  protocol::Message ask(std::uint64_t sequence) {
    protocol::Message request;
    request.header.type = protocol::MessageType::get_diag;
    request.header.sender = 3;
    request.header.sequence = sequence;
    std::array<std::uint8_t, protocol::kMaxDatagram> out{};
    const Result<std::size_t> size = protocol::seal(for_robot(request), key, ByteSpan(out));
    EXPECT_TRUE(size.ok());
    EXPECT_TRUE(client.send_to(loopback, handler.control_port(), ConstByteSpan(out.data(), size.value())).ok());
    handler.step(0);
    protocol::Message answer;
    EXPECT_TRUE(client.wait_readable(1000));
    std::array<hal::UdpDatagram, 1> in{};
    EXPECT_EQ(client.receive_batch(Span<hal::UdpDatagram>(in)), 1U);
    const Result<protocol::FrameView> frame = protocol::parse_frame(ConstByteSpan(in[0].bytes.data(), in[0].size));
    EXPECT_TRUE(frame.ok());
    if (!frame.ok()) return answer;
    EXPECT_TRUE(protocol::verify_frame(frame.value(), key).ok());
    const Result<protocol::Message> decoded = protocol::decode_payload(frame.value().header, frame.value().payload);
    EXPECT_TRUE(decoded.ok());
    return decoded.ok() ? decoded.value() : answer;
  }

};

TEST(SocketHandlerDiag, AnswersTheLatestPublishedSnapshot) {
  ASSERT_TRUE(protocol::init_crypto().ok());
  Seqlock<protocol::DiagPayload> published;
  SocketHandlerPorts ports;
  ports.diag = &published;
  Bench b(ports);
  const std::uint64_t base = static_cast<std::uint64_t>(kNow) + 1'000'000'000ULL;

  const protocol::Message before = b.ask(base);
  EXPECT_EQ(before.header.type, protocol::MessageType::diag);
  EXPECT_EQ(before.diag.cycle, 0U);  // nothing published yet
  EXPECT_EQ(before.diag.count, 0U);

  protocol::DiagPayload snapshot{};
  snapshot.cycle = 5070;
  snapshot.sweeps = 22;
  snapshot.count = 23;
  snapshot.slaves[19].ports[0] = protocol::DiagPortRecord{5, 0, 0, 0};  // l_elbow port 0: the damaged cable
  snapshot.slaves[19].warned = 0x01;
  snapshot.slaves[19].warned_before = 0x01;
  snapshot.slaves[20].ports[0] = protocol::DiagPortRecord{0, 0, 5, 0};
  snapshot.slaves[22].reads = 22;
  published.write(snapshot);

  const protocol::Message after = b.ask(base + 1);
  EXPECT_EQ(after.header.type, protocol::MessageType::diag);
  EXPECT_EQ(after.diag.cycle, 5070U);
  EXPECT_EQ(after.diag.sweeps, 22U);
  EXPECT_EQ(after.diag.count, 23U);
  EXPECT_EQ(after.diag.slaves[19].ports[0].invalid_frames, 5U);
  EXPECT_EQ(after.diag.slaves[19].warned, 0x01);
  EXPECT_EQ(after.diag.slaves[19].warned_before, 0x01);
  EXPECT_EQ(after.diag.slaves[20].ports[0].forwarded_errors, 5U);
  EXPECT_EQ(after.diag.slaves[22].reads, 22U);
  EXPECT_EQ(b.handler.counters().accepted, 2U);
}

}  // namespace
}  // namespace rescue::app
