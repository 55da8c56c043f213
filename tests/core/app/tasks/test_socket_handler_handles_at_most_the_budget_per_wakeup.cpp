// The socket handler's bounded work under a flood (docs/protocol.md "Checks and rejections"): one
// wake-up handles at most SocketHandler::kBudget (config::kSocketDatagramsPerWakeup) datagrams, both
// ports together, whatever is queued; the rest waits for the next wake-up and is counted there, every
// one under its reason; an authentic request queued behind a flood is still answered once it drains.
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

protocol::Key test_key() {
  protocol::Key k{};
  k.fill(0x5A);
  return k;
}

struct Bench : test::LoopbackSocketHandler {
  Bench() : LoopbackSocketHandler(SocketHandlerPorts{}, test_key()) {}
  // `n` datagrams of garbage (malformed: no magic) to a port; loopback queues them before send returns.
  void garbage(std::uint16_t port, std::size_t n) {
    const std::array<std::uint8_t, 12> junk{'n', 'o', 't', ' ', 'R', 'M', 'C', 'P', 0, 1, 2, 3};
    for (std::size_t i = 0; i < n; ++i) ASSERT_TRUE(client.send_to(loopback, port, ConstByteSpan(junk)).ok());
  }

};

std::uint64_t rejected(const SocketCounters& c) {
  std::uint64_t sum = 0;
  for (const std::uint64_t r : c.rejected) sum += r;
  return sum;
}

TEST(SocketHandlerBudget, OneWakeupHandlesAtMostTheBudgetBothPortsTogether) {
  Bench b;
  constexpr std::size_t kEach = SocketHandler::kBudget - 10;  // more than the budget in all, less per port
  b.garbage(b.handler.control_port(), kEach);
  b.garbage(b.handler.sensor_port(), kEach);

  b.handler.step(0);
  EXPECT_EQ(b.handler.counters().datagrams, SocketHandler::kBudget);
  EXPECT_EQ(b.handler.counters().budget_exhausted, 1U);
  EXPECT_EQ(b.handler.max_per_wakeup(), SocketHandler::kBudget);

  b.handler.step(0);
  EXPECT_EQ(b.handler.counters().datagrams, 2 * kEach);
  EXPECT_EQ(b.handler.counters().budget_exhausted, 1U);
  EXPECT_EQ(b.handler.max_per_wakeup(), SocketHandler::kBudget);
  EXPECT_EQ(b.handler.counters().wakeups, 2U);
  // Every one counted, under its reason; none accepted.
  EXPECT_EQ(b.handler.counters().accepted, 0U);
  EXPECT_EQ(b.handler.counters().rejected[static_cast<std::size_t>(protocol::Rejection::malformed)], 2 * kEach);
  EXPECT_EQ(rejected(b.handler.counters()), 2 * kEach);
}

TEST(SocketHandlerBudget, AnAuthenticRequestBehindAFloodIsAnsweredOnceItDrains) {
  Bench b;
  constexpr std::size_t kFlood = 2 * SocketHandler::kBudget + 5;
  b.garbage(b.handler.control_port(), kFlood);
  protocol::Message request;
  request.header.version = protocol::kVersion;
  request.header.type = protocol::MessageType::get_status;
  request.header.sender = 3;
  request.header.sequence = static_cast<std::uint64_t>(kNow);
  std::array<std::uint8_t, protocol::kMaxDatagram> out{};
  const Result<std::size_t> size = protocol::seal(b.for_robot(request), b.key, ByteSpan(out));
  ASSERT_TRUE(size.ok());
  ASSERT_TRUE(b.client.send_to(b.loopback, b.handler.control_port(), ConstByteSpan(out.data(), size.value())).ok());

  std::size_t wakeups = 0;
  while (b.handler.counters().accepted == 0 && wakeups < 10) {
    b.handler.step(0);
    ++wakeups;
    EXPECT_LE(b.handler.max_per_wakeup(), SocketHandler::kBudget);
  }
  EXPECT_EQ(wakeups, kFlood / SocketHandler::kBudget + 1);  // ceil((kFlood + 1) / kBudget)
  EXPECT_EQ(b.handler.counters().accepted, 1U);
  EXPECT_EQ(b.handler.counters().datagrams, kFlood + 1);
  EXPECT_EQ(rejected(b.handler.counters()), kFlood);

  ASSERT_TRUE(b.client.wait_readable(1000));
  std::array<hal::UdpDatagram, 1> in{};
  ASSERT_EQ(b.client.receive_batch(Span<hal::UdpDatagram>(in)), 1U);
  const Result<protocol::FrameView> frame = protocol::parse_frame(ConstByteSpan(in[0].bytes.data(), in[0].size));
  ASSERT_TRUE(frame.ok());
  EXPECT_TRUE(protocol::verify_frame(frame.value(), b.key).ok());
  EXPECT_EQ(frame.value().header.type, protocol::MessageType::status);
}

}  // namespace
}  // namespace rescue::app
