// libFuzzer target: the UDP protocol's decoder (docs/protocol.md) on arbitrary datagrams, and the
// replay-window file decoder on arbitrary files. Beyond "no crash": a decoded message re-encodes to
// the same payload bytes.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "core/app/operator_protocol/protocol_codec.hpp"
#include "core/app/operator_protocol/replay_window.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rescue;
  using namespace rescue::app::protocol;
  (void)decode_replay_file(ConstByteSpan(data, size));
  const Result<FrameView> frame = parse_frame(ConstByteSpan(data, size));
  // Also the payload decoders directly, whatever the structure: type from the first byte.
  if (size > 0) {
    Header h;
    h.type = static_cast<MessageType>(data[0]);
    (void)decode_payload(h, ConstByteSpan(data + 1, size - 1 > kMaxPayload ? kMaxPayload : size - 1));
  }
  if (!frame.ok()) return 0;
  if (frame.value().payload.size() > kMaxPayload || frame.value().tag.size() != kTagSize) std::abort();
  const Result<Message> m = decode_payload(frame.value().header, frame.value().payload);
  if (!m.ok()) return 0;
  std::array<std::uint8_t, kMaxPayload> again{};
  const Result<std::size_t> n = encode_payload(m.value(), ByteSpan(again));
  if (!n.ok() || n.value() != frame.value().payload.size()) std::abort();
  if (std::memcmp(again.data(), frame.value().payload.data(), n.value()) != 0) std::abort();
  return 0;
}
