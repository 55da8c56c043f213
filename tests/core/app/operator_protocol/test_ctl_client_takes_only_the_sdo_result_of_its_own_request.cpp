// An sdo_result echoes its request's sequence (docs/protocol.md "Message types"), and ctl takes only
// the one that echoes its own request: an authentic sdo_result recorded earlier in the same epoch
// (an upload that succeeded), replayed ahead of the robot's answer, is not taken for it. Before, ctl
// checked the echo of replies and epoch answers only and printed the recorded result as its own.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <thread>

#include "core/app/operator_protocol/ctl_client.hpp"
#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/protocol_codec.hpp"
#include "hal/net/udp_socket.hpp"

namespace rescue::app {
namespace {

constexpr std::uint32_t kRobot = 7;
constexpr std::uint64_t kEpoch = 0x1122334455667788ULL;
constexpr std::uint32_t kAbortCode = 0x06020000;  // object does not exist

void send(hal::UdpSocket& socket, const protocol::Key& key, protocol::Message& m, std::uint64_t sequence,
          const hal::UdpDatagram& to) {
  m.header.version = protocol::kVersion;
  m.header.sender = 0;
  m.header.robot = kRobot;
  m.header.epoch = kEpoch;
  m.header.sequence = sequence;
  std::array<std::uint8_t, protocol::kMaxDatagram> out{};
  const Result<std::size_t> size = protocol::seal(m, key, ByteSpan(out));
  ASSERT_TRUE(size.ok());
  ASSERT_TRUE(socket.send_to(to.address, to.port, ConstByteSpan(out.data(), size.value())).ok());
}

// A robot that answers get_epoch, and an sdo_upload first with a recorded result of another request
// (status ok) and then with its own (aborted).
void serve(hal::UdpSocket& socket, const protocol::Key& key, const std::atomic<bool>& done) {
  std::array<hal::UdpDatagram, 1> in{};
  std::uint64_t sent = 1;
  while (!done.load()) {
    if (!socket.wait_readable(10) || socket.receive_batch(Span<hal::UdpDatagram>(in)) != 1) continue;
    const Result<protocol::FrameView> frame = protocol::parse_frame(ConstByteSpan(in[0].bytes.data(), in[0].size));
    if (!frame.ok() || !protocol::verify_frame(frame.value(), key).ok()) continue;
    const Result<protocol::Message> request = protocol::decode_payload(frame.value().header, frame.value().payload);
    if (!request.ok()) continue;
    const std::uint64_t asked = request.value().header.sequence;
    protocol::Message answer;
    if (request.value().header.type == protocol::MessageType::get_epoch) {
      answer.header.type = protocol::MessageType::epoch;
      answer.epoch.request_sequence = asked;
      send(socket, key, answer, ++sent, in[0]);
      continue;
    }
    if (request.value().header.type != protocol::MessageType::sdo_upload) continue;
    answer.header.type = protocol::MessageType::sdo_result;
    answer.sdo_result.request_type = protocol::MessageType::sdo_upload;
    answer.sdo_result.joint = request.value().sdo.joint;
    answer.sdo_result.index = request.value().sdo.index;
    answer.sdo_result.subindex = request.value().sdo.subindex;
    answer.sdo_result.request_sequence = asked - 1000;  // recorded from an earlier upload
    answer.sdo_result.status = protocol::SdoStatus::ok;
    answer.sdo_result.size = 4;
    answer.sdo_result.data = {1, 2, 3, 4};
    send(socket, key, answer, ++sent, in[0]);
    answer.sdo_result.request_sequence = asked;
    answer.sdo_result.status = protocol::SdoStatus::aborted;
    answer.sdo_result.abort_code = kAbortCode;
    answer.sdo_result.size = 0;
    answer.sdo_result.data = {};
    send(socket, key, answer, ++sent, in[0]);
  }
}

TEST(CtlClientSdoResult, ARecordedResultOfAnotherRequestIsNotTakenForItsOwn) {
  protocol::Key key{};
  key.fill(0x5A);
  hal::UdpSocket robot;
  ASSERT_TRUE(robot.open("127.0.0.1", 0).ok());
  std::atomic<bool> done{false};
  std::thread server([&] { serve(robot, key, done); });
  CtlTarget target;
  target.address = hal::parse_ipv4("127.0.0.1").value();
  target.port = robot.local_port();
  target.key = key;
  target.sender = 1;  // ctl's default --sender
  target.timeout_ms = 3000;
  protocol::Message request;
  request.header.type = protocol::MessageType::sdo_upload;
  request.sdo.joint = 3;
  request.sdo.index = 0x6064;
  request.sdo.subindex = 0;
  const Result<protocol::Message> answer = ctl_exchange(target, request);
  done.store(true);
  server.join();
  ASSERT_TRUE(answer.ok()) << answer.error().what;
  ASSERT_EQ(answer.value().header.type, protocol::MessageType::sdo_result);
  EXPECT_EQ(answer.value().sdo_result.status, protocol::SdoStatus::aborted);
  EXPECT_EQ(answer.value().sdo_result.abort_code, kAbortCode);
}

}  // namespace
}  // namespace rescue::app
