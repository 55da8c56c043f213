// libFuzzer target: the mailbox and CoE decoders on arbitrary bytes must never read out of
// bounds; whatever decodes must re-encode (the encoder accepts every decoded SDO) and decode
// again to the same kind, index and subindex.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "ecat/mailbox/coe.hpp"
#include "ecat/mailbox/mailbox.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rescue::ecat;
  const rescue::ConstByteSpan bytes(data, size);
  auto m = mbx::decode(bytes);
  if (m.ok()) {
    if (m.value().data.size() != m.value().header.length) std::abort();
    (void)mbx::decode_error_reply(m.value());
  }
  auto c = coe::decode(bytes);
  if (!c.ok()) return 0;
  const coe::Message& msg = c.value();
  if (msg.service != coe::Service::sdo_request && msg.service != coe::Service::sdo_response) return 0;
  coe::Sdo sdo = msg.sdo;
  if (sdo.expedited && (sdo.data.empty() || sdo.data.size() > coe::kMaxExpeditedSize)) std::abort();
  static std::array<std::uint8_t, 70000> out{};
  auto n = coe::encode(rescue::ByteSpan(out), msg.mailbox, sdo);
  if (!n.ok()) return 0;  // e.g. an expedited size of zero bytes announced with s=0
  auto again = coe::decode(rescue::ConstByteSpan(out.data(), n.value()));
  if (!again.ok()) std::abort();
  if (again.value().sdo.kind != sdo.kind || again.value().sdo.index != sdo.index ||
      again.value().sdo.subindex != sdo.subindex) {
    std::abort();
  }
  return 0;
}
