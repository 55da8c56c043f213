// libFuzzer target: CaptureReader on arbitrary bytes (a capture file someone hands to `decode`)
// never reads outside them; every frame it returns lies inside the input, frame numbers count up
// by one, the reader always moves forward, and each frame goes through the link-layer and frame
// decoders (Ethernet, Linux cooked SLL/SLL2) as `decode` does.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "ecat/capture/capture_reader.hpp"
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
  auto reader = CaptureReader::open(ConstByteSpan(data, size));
  if (!reader.ok()) {
    check(reader.error().detail1 <= size);
    return 0;
  }
  CapturedFrame frame;
  std::uint32_t expected_number = 1;
  std::size_t last_offset = reader.value().offset();
  for (;;) {
    const Result<bool> more = reader.value().next(frame);
    if (!more.ok()) {
      check(more.error().detail0 == expected_number);
      check(more.error().detail1 <= size);
      const Result<bool> again = reader.value().next(frame);  // sticky
      check(!again.ok() && again.error().what == more.error().what);
      break;
    }
    if (!more.value()) {
      check(reader.value().offset() == size);
      break;
    }
    check(frame.number == expected_number++);
    check(frame.bytes.data() >= data && frame.bytes.data() + frame.bytes.size() <= data + size);
    check(reader.value().offset() > last_offset && reader.value().offset() <= size);
    last_offset = reader.value().offset();
    unsigned sum = 0;
    const auto parsed = decode_captured_frame(frame.link_type, frame.bytes);
    check(parsed.ok() || is_supported_link_type(frame.link_type) || std::strcmp(parsed.error().what, "link type") == 0);
    if (parsed.ok()) {
      check(parsed.value().header().ecat_end() <= frame.bytes.size());
      for (const DatagramView d : parsed.value()) sum += d.length() + d.wkc();
    }
    (void)sum;
  }
  check(reader.value().frames_read() == expected_number - 1);
  return 0;
}
