// Fuzzes the simulated drive's CoE server (SDO and SDO Information) with what a master may write
// into SM0: arbitrary mailbox bytes, any SM1 length from the first input byte, answered in any AL
// state, and the following fragments of the same request. Every answer must fit SM1. Then the same
// bytes as a sequence of mailbox messages (each one length byte, then that many bytes) served in
// turn with one segmented-transfer state, as the drive serves them: initiates followed by upload and
// download segments (toggle, sizes, the value collected) reach the segmented paths; every answer
// must fit SM1 there too, and a transfer's offset never passes its size. Seeds (seeds-fuzz_sdo_server/):
// a segmented upload of 0x100A and a segmented download of 0x2010 in a 128-byte mailbox.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "drivers/sim/coe/coe_sdo_server.hpp"
#include "drivers/joint/device_identity.hpp"
#include "drivers/sim/devices/joint_drive_objects.hpp"

using namespace rescue;
using namespace rescue::drivers;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static JointDriveObjects objects(joint_index_by_name("l_elbow"), slave_position_of_joint(joint_index_by_name("l_elbow")));
  if (size < 2) return 0;
  // SM1 lengths a master may configure: 16..271 bytes.
  const std::size_t sm1 = 16 + data[0];
  const auto state = static_cast<ecat::reg::AlState>(1U << (data[1] % 4U));
  const ConstByteSpan request(data + 2, size - 2);
  std::array<std::uint8_t, 272> response{};
  const std::size_t n = serve_sdo(request, objects.od(), state, ByteSpan(response.data(), sm1), 1);
  if (n > sm1) std::abort();
  for (std::uint16_t fragment = 1; fragment < 4; ++fragment) {
    const std::size_t f = serve_sdo_fragment(request, objects.od(), ByteSpan(response.data(), sm1), 2, fragment);
    if (f > sm1) std::abort();
  }
  SdoSegmentState segments;
  std::size_t at = 0;
  std::uint8_t counter = 1;
  while (at < request.size()) {
    const std::size_t length = request[at];
    const std::size_t take = length < request.size() - at - 1 ? length : request.size() - at - 1;
    const ConstByteSpan message = request.subspan(at + 1, take);
    at += 1 + take;
    counter = static_cast<std::uint8_t>(counter % 7U + 1U);
    const std::size_t m = serve_sdo(message, objects.od(), state, ByteSpan(response.data(), sm1), counter, &segments);
    if (m > sm1) std::abort();
    if (segments.active && (segments.offset > segments.size || segments.size > (segments.upload ? 255U : SdoSegmentState::kCapacity))) {
      std::abort();
    }
  }
  return 0;
}
