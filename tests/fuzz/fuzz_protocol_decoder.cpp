// libFuzzer target: the UDP protocol's decoder (docs/protocol.md) on arbitrary datagrams. Beyond "no
// crash": a parsed header (version 2: sender, robot id, epoch, sequence, payload length) re-encodes
// to the same header bytes, only get_epoch leaves the robot id or the epoch 0, and a decoded message
// re-encodes to the same payload bytes. Seeds (seeds-fuzz_protocol_decoder/): payloads of a type
// (first byte the type), and whole datagrams of version 2: get_epoch, the epoch answer, an enable for
// robot 3 in an epoch, a reply, an sdo_upload (their tags are not checked here); payloads of
// sdo_upload, sdo_download and sdo_result (a segmented upload, a refusal), and an upload and its
// result addressed by slave position (a junction); a get_sii and an sii answer (a junction's image);
// a reg_read and its reg_result (an AL status read, and a lost slave's refusal); a states request
// and its states_result (reached, refused in service, refused by the slave); a rescan and its
// rescan_result (four slaves missing, an incomplete one); a graph of the tree and one of the ring open
// between positions 18 and 19; an sdo_info (the OD list by position, an entry description) and its
// sdo_info_result (a drive's OD list, a junction's refusal).
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "core/app/operator_protocol/protocol_codec.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rescue;
  using namespace rescue::app::protocol;
  const Result<FrameView> frame = parse_frame(ConstByteSpan(data, size));
  // Also the payload decoders directly, whatever the structure: type from the first byte.
  if (size > 0) {
    Header h;
    h.type = static_cast<MessageType>(data[0]);
    (void)decode_payload(h, ConstByteSpan(data + 1, size - 1 > kMaxPayload ? kMaxPayload : size - 1));
  }
  if (!frame.ok()) return 0;
  if (frame.value().payload.size() > kMaxPayload || frame.value().tag.size() != kTagSize) std::abort();
  const Header& h = frame.value().header;
  std::array<std::uint8_t, kHeaderSize> header{};
  encode_header(h, header.data());
  if (std::memcmp(header.data(), data, kHeaderSize) != 0) std::abort();
  const bool asks_epoch = h.type == MessageType::get_epoch;
  if (asks_epoch ? h.epoch != 0 : (h.epoch == 0 || h.robot == kAnyRobot)) std::abort();
  const Result<Message> m = decode_payload(frame.value().header, frame.value().payload);
  if (!m.ok()) return 0;
  std::array<std::uint8_t, kMaxPayload> again{};
  const Result<std::size_t> n = encode_payload(m.value(), ByteSpan(again));
  if (!n.ok() || n.value() != frame.value().payload.size()) std::abort();
  if (std::memcmp(again.data(), frame.value().payload.data(), n.value()) != 0) std::abort();
  return 0;
}
