// ctl upload/download inside the socket handler (docs/protocol.md "SDO transfers"): an authentic
// sdo_upload goes to the EtherCAT handler's queue (TaskLinks::sdo_requests) and is answered with
// sdo_result only when the handler's result comes back, to the address it came from, with the
// request's sequence and the reason in words; a second transfer while one is in flight (another
// sender's) is answered busy at once and never reaches the queue; a transfer the handler does not
// answer within kSdoAnswerLimit is answered no_answer, and the handler's late result is dropped; an
// sdo_info (ctl sdos) is one such transfer, answered with its own sdo_info_result. A result that is
// a damaged record of the segment (a status, target, type or size the handler never writes) is
// refused and counted, never sent: the transfer is answered no_answer at its deadline.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>

#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/protocol_codec.hpp"
#include "core/app/tasks/socket_handler.hpp"
#include "core/concurrency/spsc_message_port.hpp"
#include "hal/net/udp_socket.hpp"
#include "tests/support/loopback_socket_handler.hpp"

namespace rescue::app {
namespace {

constexpr std::int64_t kNow = test::LoopbackSocketHandler::kNow;
using protocol::MessageType;
using protocol::SdoStatus;

struct Bench : test::LoopbackSocketHandler {
  explicit Bench(const SocketHandlerPorts& ports) : LoopbackSocketHandler(ports, protocol::Key{}) {}
  void send_upload(std::uint32_t sender, std::uint64_t sequence, std::uint16_t index) {
    protocol::Message request;
    request.header.type = MessageType::sdo_upload;
    request.header.sender = sender;
    request.header.sequence = sequence;
    request.sdo.joint = 4;
    request.sdo.index = index;
    std::array<std::uint8_t, protocol::kMaxDatagram> out{};
    const Result<std::size_t> size = protocol::seal(for_robot(request), key, ByteSpan(out));
    ASSERT_TRUE(size.ok());
    ASSERT_TRUE(client.send_to(loopback, handler.control_port(), ConstByteSpan(out.data(), size.value())).ok());
  }
  void send_info(std::uint32_t sender, std::uint64_t sequence, std::uint16_t offset) {
    protocol::Message request;
    request.header.type = MessageType::sdo_info;
    request.header.sender = sender;
    request.header.sequence = sequence;
    request.sdo_info.target = protocol::SdoTarget::slave;
    request.sdo_info.slave = 13;
    request.sdo_info.op = protocol::SdoInfoOp::od_list;
    request.sdo_info.index = 1;
    request.sdo_info.offset = offset;
    std::array<std::uint8_t, protocol::kMaxDatagram> out{};
    const Result<std::size_t> size = protocol::seal(for_robot(request), key, ByteSpan(out));
    ASSERT_TRUE(size.ok());
    ASSERT_TRUE(client.send_to(loopback, handler.control_port(), ConstByteSpan(out.data(), size.value())).ok());
  }
  // The next answer, decoded (type reply with outcome refused when none came within 200 ms).
  protocol::Message answer() {
    protocol::Message none;
    none.header.type = MessageType::reply;
    if (!client.wait_readable(200)) return none;
    std::array<hal::UdpDatagram, 1> in{};
    if (client.receive_batch(Span<hal::UdpDatagram>(in)) != 1) return none;
    const Result<protocol::FrameView> frame = protocol::parse_frame(ConstByteSpan(in[0].bytes.data(), in[0].size));
    EXPECT_TRUE(frame.ok());
    if (!frame.ok()) return none;
    EXPECT_TRUE(protocol::verify_frame(frame.value(), key).ok());
    const Result<protocol::Message> decoded = protocol::decode_payload(frame.value().header, frame.value().payload);
    EXPECT_TRUE(decoded.ok());
    return decoded.ok() ? decoded.value() : none;
  }
};

struct Queues {
  SpscQueue<SdoLinkRequest, config::kSdoQueueDepth> requests;
  SpscQueue<SdoLinkResult, config::kSdoQueueDepth> results;
  SpscMessageSink<SdoLinkRequest, config::kSdoQueueDepth> socket_requests{requests};
  SpscMessageSource<SdoLinkResult, config::kSdoQueueDepth> socket_results{results};
  SocketHandlerPorts ports() {
    SocketHandlerPorts p;
    p.sdo_requests = &socket_requests;
    p.sdo_results = &socket_results;
    return p;
  }
};

constexpr std::uint64_t kBase = static_cast<std::uint64_t>(kNow) + 1'000'000'000ULL;

// Sender 3's upload of `index` at sequence kBase, one wake-up at time 0: what reached the handler's queue.
SdoLinkRequest first_transfer(Bench& b, Queues& q, std::uint16_t index) {
  b.send_upload(3, kBase, index);
  b.handler.step(0);
  SdoLinkRequest forwarded;
  EXPECT_TRUE(q.requests.try_pop(forwarded));
  return forwarded;
}

TEST(SocketHandlerSdo, OneTransferInFlightTheSecondBusyAndEachAnswered) {
  ASSERT_TRUE(protocol::init_crypto().ok());
  Queues q;
  Bench b(q.ports());
  const std::uint64_t base = kBase;
  SdoLinkRequest forwarded = first_transfer(b, q, 0x100A);
  EXPECT_FALSE(forwarded.download);
  EXPECT_EQ(forwarded.sdo.index, 0x100A);
  EXPECT_EQ(forwarded.sdo.joint, 4);
  EXPECT_EQ(b.answer().header.type, MessageType::reply) << "no answer before the handler's result";

  b.send_upload(5, base + 1, 0x1008);  // another operator station meanwhile
  b.handler.step(1'000'000);
  const protocol::Message busy = b.answer();
  ASSERT_EQ(busy.header.type, MessageType::sdo_result);
  EXPECT_EQ(busy.sdo_result.status, SdoStatus::busy);
  EXPECT_EQ(busy.sdo_result.request_sequence, base + 1);
  EXPECT_EQ(busy.sdo_result.index, 0x1008);
  EXPECT_STREQ(busy.sdo_result.text.data(), "another SDO transfer is in flight; try again");
  EXPECT_FALSE(q.requests.try_pop(forwarded)) << "the busy one never reached the handler";

  SdoLinkResult done;
  done.id = forwarded.id;
  done.result.request_type = MessageType::sdo_upload;
  done.result.joint = 4;
  done.result.index = 0x100A;
  done.result.status = SdoStatus::ok;
  done.result.flags = protocol::kSdoSegmented;
  done.result.size = 3;
  std::memcpy(done.result.data.data(), "3.2", 3);
  ASSERT_TRUE(q.results.try_push(done));
  b.handler.step(2'000'000);
  const protocol::Message ok = b.answer();
  ASSERT_EQ(ok.header.type, MessageType::sdo_result);
  EXPECT_EQ(ok.sdo_result.status, SdoStatus::ok);
  EXPECT_EQ(ok.sdo_result.request_sequence, base);
  EXPECT_EQ(ok.sdo_result.size, 3U);
  EXPECT_STREQ(ok.sdo_result.text.data(), "done (segmented)");

  // Free again: the next one is forwarded.
  b.send_upload(5, base + 2, 0x1008);
  b.handler.step(3'000'000);
  ASSERT_TRUE(q.requests.try_pop(forwarded));
  EXPECT_EQ(forwarded.sdo.index, 0x1008);
}

TEST(SocketHandlerSdo, AHandlerThatDoesNotAnswerGetsNoAnswerAndItsLateResultIsDropped) {
  ASSERT_TRUE(protocol::init_crypto().ok());
  Queues q;
  Bench b(q.ports());
  const std::uint64_t base = kBase;
  const SdoLinkRequest forwarded = first_transfer(b, q, 0x603F);
  EXPECT_EQ(forwarded.sdo.index, 0x603F);
  b.handler.step(SocketHandler::kSdoAnswerLimit);  // not past it yet
  EXPECT_EQ(b.answer().header.type, MessageType::reply);
  b.handler.step(SocketHandler::kSdoAnswerLimit + 1);
  const protocol::Message late = b.answer();
  ASSERT_EQ(late.header.type, MessageType::sdo_result);
  EXPECT_EQ(late.sdo_result.status, SdoStatus::no_answer);
  EXPECT_EQ(late.sdo_result.request_sequence, base);
  EXPECT_EQ(late.sdo_result.index, 0x603F);

  SdoLinkResult after;
  after.id = forwarded.id;
  after.result.request_type = MessageType::sdo_upload;
  ASSERT_TRUE(q.results.try_push(after));
  b.handler.step(SocketHandler::kSdoAnswerLimit + 2);
  EXPECT_EQ(b.answer().header.type, MessageType::reply) << "the late result is not sent a second time";
}

TEST(SocketHandlerSdo, ADamagedResultIsRefusedCountedAndTheTransferAnsweredNoAnswer) {
  ASSERT_TRUE(protocol::init_crypto().ok());
  Queues q;
  Bench b(q.ports());
  const SdoLinkRequest forwarded = first_transfer(b, q, 0x100A);
  SdoLinkResult damaged;
  damaged.id = forwarded.id;
  damaged.result.request_type = MessageType::sdo_upload;
  damaged.result.index = 0x100A;
  const unsigned char status = 0x7E;  // no SdoStatus
  std::memcpy(&damaged.result.status, &status, 1);
  ASSERT_TRUE(q.results.try_push(damaged));
  SdoLinkResult long_value = damaged;
  long_value.result.status = SdoStatus::ok;
  long_value.result.size = 300;  // beyond the record's 256 bytes of data
  ASSERT_TRUE(q.results.try_push(long_value));
  b.handler.step(1'000'000);
  EXPECT_EQ(b.answer().header.type, MessageType::reply) << "nothing sent from a damaged record";
  EXPECT_EQ(b.handler.damaged_records(), 2U);
  b.handler.step(SocketHandler::kSdoAnswerLimit + 1);
  const protocol::Message late = b.answer();
  ASSERT_EQ(late.header.type, MessageType::sdo_result);
  EXPECT_EQ(late.sdo_result.status, SdoStatus::no_answer);
  EXPECT_EQ(late.sdo_result.request_sequence, kBase);
}

}  // namespace
}  // namespace rescue::app

namespace rescue::app {
namespace {

// ctl sdos: an sdo_info goes to the same queue as an upload with its request (info_op, offset, the
// slave's position), and the handler's result comes back as sdo_info_result echoing the request
// with the window of the data and the whole length; while it is in flight an upload is busy.
TEST(SocketHandlerSdo, AnSdoInformationRequestIsOneTransferAnsweredWithItsOwnResult) {
  ASSERT_TRUE(protocol::init_crypto().ok());
  Queues q;
  Bench b(q.ports());
  b.send_info(3, kBase, 4);
  b.handler.step(0);
  SdoLinkRequest forwarded;
  ASSERT_TRUE(q.requests.try_pop(forwarded));
  EXPECT_EQ(forwarded.info_op, protocol::SdoInfoOp::od_list);
  EXPECT_EQ(forwarded.info_offset, 4);
  EXPECT_FALSE(forwarded.download);
  EXPECT_EQ(forwarded.sdo.target, protocol::SdoTarget::slave);
  EXPECT_EQ(forwarded.sdo.slave, 13);
  EXPECT_EQ(forwarded.sdo.index, 1);

  b.send_upload(5, kBase + 1, 0x1008);
  b.handler.step(1'000'000);
  const protocol::Message busy = b.answer();
  ASSERT_EQ(busy.header.type, MessageType::sdo_result);
  EXPECT_EQ(busy.sdo_result.status, SdoStatus::busy);

  SdoLinkResult done;
  done.id = forwarded.id;
  done.result.request_type = MessageType::sdo_info;
  done.result.target = protocol::SdoTarget::slave;
  done.result.slave = 13;
  done.result.index = 1;
  done.result.status = SdoStatus::ok;
  done.result.info_total = 10;
  done.result.size = 6;
  std::memcpy(done.result.data.data(), "\x00\x10\x01\x10\x08\x10", 6);
  ASSERT_TRUE(q.results.try_push(done));
  b.handler.step(2'000'000);
  const protocol::Message ok = b.answer();
  ASSERT_EQ(ok.header.type, MessageType::sdo_info_result);
  const protocol::SdoInfoResultPayload& r = ok.sdo_info_result;
  EXPECT_EQ(r.request_sequence, kBase);
  EXPECT_EQ(r.status, SdoStatus::ok);
  EXPECT_EQ(r.request.op, protocol::SdoInfoOp::od_list);
  EXPECT_EQ(r.request.offset, 4);
  EXPECT_EQ(r.request.slave, 13);
  EXPECT_EQ(r.total, 10);
  EXPECT_EQ(r.length, 6);
  EXPECT_EQ(r.data[1], 0x10);
  EXPECT_STREQ(r.text.data(), "done");
}

}  // namespace
}  // namespace rescue::app
