// The next authentic datagram a test's station socket receives: parsed, its tag verified under the
// key, its payload decoded (docs/protocol.md), as ctl checks the robot's answers.
#pragma once

#include <array>
#include <cstdint>

#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/protocol_codec.hpp"
#include "hal/net/udp_socket.hpp"

namespace rescue::test {

// False when nothing arrives within `timeout_ms`, or what arrives is not authentic, or (with
// `from_port` nonzero) comes from another port.
inline bool receive_authentic(hal::UdpSocket& socket, const app::protocol::Key& key, int timeout_ms,
                              app::protocol::Message& out, std::uint16_t from_port = 0) {
  namespace protocol = app::protocol;
  if (!socket.wait_readable(timeout_ms)) return false;
  std::array<hal::UdpDatagram, 1> in{};
  if (socket.receive_batch(Span<hal::UdpDatagram>(in)) != 1) return false;
  if (from_port != 0 && in[0].port != from_port) return false;
  const Result<protocol::FrameView> f = protocol::parse_frame(ConstByteSpan(in[0].bytes.data(), in[0].size));
  if (!f.ok() || !protocol::verify_frame(f.value(), key).ok()) return false;
  const Result<protocol::Message> m = protocol::decode_payload(f.value().header, f.value().payload);
  if (!m.ok()) return false;
  out = m.value();
  return true;
}

}  // namespace rescue::test
