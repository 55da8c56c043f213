#include "core/app/operator_protocol/ctl_client.hpp"

#include <ctime>

#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/protocol_codec.hpp"
#include "hal/net/udp_socket.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {
namespace {

std::uint64_t unix_ns() noexcept {
  timespec ts{};
  (void)clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::uint64_t>(ts.tv_sec) * 1'000'000'000ULL + static_cast<std::uint64_t>(ts.tv_nsec);
}

// Sends `request` and waits until `deadline` for the robot's authentic answer to it: sender 0, for
// `robot` (any when kAnyRobot) in `epoch` (any when 0), a reply, an sdo_result, a states_result, a
// rescan_result or an epoch answer echoing its sequence.
Result<protocol::Message> round_trip(hal::UdpSocket& socket, const CtlTarget& target, protocol::Message& request,
                                     hal::Nanoseconds deadline) noexcept {
  std::array<std::uint8_t, protocol::kMaxDatagram> out{};
  const Result<std::size_t> size = protocol::seal(request, target.key, ByteSpan(out));
  if (!size.ok()) return size.error();
  RESCUE_TRY(socket.send_to(target.address, target.port, ConstByteSpan(out.data(), size.value())));
  hal::MonotonicClock clock;
  std::array<hal::UdpDatagram, 1> in{};
  const protocol::Header& asked = request.header;
  const bool asks_epoch = asked.type == protocol::MessageType::get_epoch;
  while (clock.now() < deadline) {
    const auto left_ms = static_cast<int>((deadline - clock.now()) / hal::kNsPerMs) + 1;
    if (!socket.wait_readable(left_ms)) continue;
    if (socket.receive_batch(Span<hal::UdpDatagram>(in)) != 1) continue;
    const hal::UdpDatagram& d = in[0];
    if (d.truncated || d.address != target.address || d.port != target.port) continue;
    const Result<protocol::FrameView> frame = protocol::parse_frame(ConstByteSpan(d.bytes.data(), d.size));
    if (!frame.ok() || !protocol::verify_frame(frame.value(), target.key).ok()) continue;
    const protocol::Header& h = frame.value().header;
    if (h.sender != 0) continue;
    if (!asks_epoch && (h.robot != asked.robot || h.epoch != asked.epoch)) continue;
    const Result<protocol::Message> m = protocol::decode_payload(h, frame.value().payload);
    if (!m.ok()) continue;
    const protocol::MessageType type = m.value().header.type;
    if (asks_epoch != (type == protocol::MessageType::epoch)) continue;
    if (asks_epoch && m.value().epoch.request_sequence != asked.sequence) continue;
    if (type == protocol::MessageType::reply && m.value().reply.request_sequence != asked.sequence) continue;
    // An sdo_result echoes its request too: a recorded one of an earlier transfer is not this one's.
    if (type == protocol::MessageType::sdo_result && m.value().sdo_result.request_sequence != asked.sequence) continue;
    if (type == protocol::MessageType::sdo_info_result && m.value().sdo_info_result.request_sequence != asked.sequence) {
      continue;
    }
    if (type == protocol::MessageType::states_result && m.value().states_result.request_sequence != asked.sequence) continue;
    if (type == protocol::MessageType::rescan_result && m.value().rescan_result.request_sequence != asked.sequence) continue;
    return m.value();
  }
  return make_error(Errc::timeout, "no authentic answer from the robot (not running, wrong port, or another key)");
}

}  // namespace

Result<protocol::Message> ctl_exchange(const CtlTarget& target, protocol::Message request) noexcept {
  hal::UdpSocket socket;
  RESCUE_TRY(socket.open("0.0.0.0", 0));
  hal::MonotonicClock clock;
  const hal::Nanoseconds deadline = clock.now() + static_cast<hal::Nanoseconds>(target.timeout_ms) * hal::kNsPerMs;
  // 1. The robot's epoch and id (docs/protocol.md "Replay protection").
  protocol::Message ask;
  ask.header.version = protocol::kVersion;
  ask.header.type = protocol::MessageType::get_epoch;
  ask.header.sender = target.sender;
  ask.header.robot = protocol::kAnyRobot;  // whichever robot is there says who it is
  ask.header.sequence = unix_ns();
  const Result<protocol::Message> epoch = round_trip(socket, target, ask, deadline);
  if (!epoch.ok()) return epoch.error();
  const protocol::Header& robot = epoch.value().header;
  if (target.robot != protocol::kAnyRobot && robot.robot != target.robot) {
    return make_error(Errc::refused, "the robot at that address has another robot id than --robot (detail: its id)",
                      robot.robot);
  }
  // 2. The request, for that robot in that epoch; its sequence above the get_epoch's.
  request.header.version = protocol::kVersion;
  request.header.sender = target.sender;
  request.header.robot = robot.robot;
  request.header.epoch = robot.epoch;
  const std::uint64_t now = unix_ns();
  request.header.sequence = now > ask.header.sequence ? now : ask.header.sequence + 1;
  Result<protocol::Message> answer = round_trip(socket, target, request, deadline);
  if (!answer.ok() && answer.error().code == Errc::timeout) {
    // The robot answered get_epoch with this key, so it runs and listens here: its replay window
    // dropped the request (docs/protocol.md "Senders"), or the request or answer was lost.
    return make_error(Errc::timeout,
                      "the robot answered get_epoch but not the request: replay window (this --sender's sequence "
                      "already passed this epoch: use another --sender or restart the robot), or lost");
  }
  return answer;
}

}  // namespace rescue::app
