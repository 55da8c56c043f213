// libFuzzer target: decode_captured_frame on arbitrary packet bytes. The first byte picks the link
// type (Ethernet, Linux cooked SLL, SLL2, or an unsupported one); the rest is the captured packet.
// It never reads outside the packet; what it accepts lies inside it, starts after the cooked
// header, and its datagrams plus zero padding tile the EtherCAT length; errors name a field and an
// offset inside the packet.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "ecat/capture/captured_link.hpp"
#include "ecat/codec/frame.hpp"

namespace {

void check(bool condition) {
  if (!condition) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rescue;        // NOLINT(google-build-using-namespace)
  using namespace rescue::ecat;  // NOLINT(google-build-using-namespace)
  if (size < 1) return 0;
  static constexpr std::uint16_t kLinks[] = {capture::kLinkTypeEthernet, capture::kLinkTypeLinuxSll,
                                             capture::kLinkTypeLinuxSll2, 101};
  const std::uint16_t link = kLinks[data[0] % 4];
  // An exactly-sized copy on the heap, so ASan sees a read one byte past the packet.
  const std::vector<std::uint8_t> packet(data + 1, data + size);
  const ConstByteSpan bytes(packet.data(), packet.size());
  const auto r = decode_captured_frame(link, bytes);
  if (!r.ok()) {
    check(r.error().what != nullptr && r.error().code != Errc::ok);
    if (link == 101) check(r.error().detail1 == 101);
    else check(r.error().detail1 <= bytes.size());
    return 0;
  }
  check(is_supported_link_type(link));
  const FrameHeader& h = r.value().header();
  check(h.ecat_end() <= bytes.size());
  if (link == capture::kLinkTypeLinuxSll) check(h.ecat_offset >= capture::kSllHeaderSize);
  if (link == capture::kLinkTypeLinuxSll2) check(h.ecat_offset >= capture::kSll2HeaderSize);
  std::size_t covered = 0;
  for (const DatagramView d : r.value()) covered += d.wire_size();
  check(covered + h.padding == h.ecat_length);
  return 0;
}
