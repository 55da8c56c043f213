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

}  // namespace

Result<protocol::Message> ctl_exchange(const CtlTarget& target, protocol::Message request) noexcept {
  hal::UdpSocket socket;
  RESCUE_TRY(socket.open("0.0.0.0", 0));
  request.header.version = protocol::kVersion;
  request.header.sender = target.sender;
  request.header.sequence = unix_ns();
  std::array<std::uint8_t, protocol::kMaxDatagram> out{};
  const Result<std::size_t> size = protocol::seal(request, target.key, ByteSpan(out));
  if (!size.ok()) return size.error();
  RESCUE_TRY(socket.send_to(target.address, target.port, ConstByteSpan(out.data(), size.value())));
  hal::MonotonicClock clock;
  const hal::Nanoseconds give_up = clock.now() + static_cast<hal::Nanoseconds>(target.timeout_ms) * hal::kNsPerMs;
  std::array<hal::UdpDatagram, 1> in{};
  while (clock.now() < give_up) {
    const auto left_ms = static_cast<int>((give_up - clock.now()) / hal::kNsPerMs) + 1;
    if (!socket.wait_readable(left_ms)) continue;
    if (socket.receive_batch(Span<hal::UdpDatagram>(in)) != 1) continue;
    const hal::UdpDatagram& d = in[0];
    if (d.truncated || d.address != target.address || d.port != target.port) continue;
    const Result<protocol::FrameView> frame = protocol::parse_frame(ConstByteSpan(d.bytes.data(), d.size));
    if (!frame.ok() || !protocol::verify_frame(frame.value(), target.key).ok()) continue;
    if (frame.value().header.sender != 0) continue;
    const Result<protocol::Message> m = protocol::decode_payload(frame.value().header, frame.value().payload);
    if (!m.ok()) continue;
    if (m.value().header.type == protocol::MessageType::reply &&
        m.value().reply.request_sequence != request.header.sequence) {
      continue;
    }
    return m.value();
  }
  return make_error(Errc::timeout, "no authentic answer from the robot (not running, wrong port, or another key)");
}

}  // namespace rescue::app
