// libFuzzer target: CaptureReader on arbitrary bytes (a capture file someone hands to `decode`)
// never reads outside them; every frame it returns lies inside the input, frame numbers count up
// by one, the reader always moves forward, and each frame goes through the link-layer and frame
// decoders (Ethernet, Linux cooked SLL/SLL2) as `decode` does. Streamed through the smallest window
// (as `decode` streams a file), the reader gives the same frames and the same end, unless the input
// holds a block larger than the window, which it refuses ("block length", capacity_exceeded).
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

// The window's own limit: a block larger than the streamed reader's window, which it may refuse only
// when the input holds that block whole (the whole-input reader reads on); an input no larger than the
// window holds no such block, and there the readers agree exactly.
bool window_limit(const rescue::Error& e, std::size_t input_size, std::size_t window_size) {
  return input_size > window_size && e.code == rescue::Errc::capacity_exceeded && std::strcmp(e.what, "block length") == 0;
}

// The input served by offset, as pread serves a file.
class InputSource final : public rescue::ecat::CaptureSource {
 public:
  InputSource(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  rescue::Result<std::size_t> read_at(std::size_t offset, rescue::ByteSpan out) noexcept override {
    if (offset >= size_) return std::size_t{0};
    const std::size_t n = out.size() < size_ - offset ? out.size() : size_ - offset;
    std::memcpy(out.data(), data_ + offset, n);
    return n;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
};

std::uint8_t g_window[rescue::ecat::CaptureReader::kMinWindow];

// The whole-input reader and the streamed one in lockstep.
void check_streamed_agrees(const std::uint8_t* data, std::size_t size) {
  using namespace rescue;        // NOLINT(google-build-using-namespace)
  using namespace rescue::ecat;  // NOLINT(google-build-using-namespace)
  InputSource source(data, size);
  auto whole = CaptureReader::open(ConstByteSpan(data, size));
  auto streamed = CaptureReader::open(source, ByteSpan(g_window, sizeof g_window));
  if (!streamed.ok() && window_limit(streamed.error(), size, sizeof g_window)) return;
  if (!whole.ok() || !streamed.ok()) {
    check(whole.ok() == streamed.ok());
    check(whole.error().code == streamed.error().code && std::strcmp(whole.error().what, streamed.error().what) == 0 &&
          whole.error().detail1 == streamed.error().detail1);
    return;
  }
  CapturedFrame a;
  CapturedFrame b;
  for (;;) {
    const Result<bool> more_b = streamed.value().next(b);
    if (!more_b.ok() && window_limit(more_b.error(), size, sizeof g_window)) return;
    const Result<bool> more_a = whole.value().next(a);
    check(more_a.ok() == more_b.ok());
    if (!more_a.ok()) {
      check(more_a.error().code == more_b.error().code && std::strcmp(more_a.error().what, more_b.error().what) == 0 &&
            more_a.error().detail0 == more_b.error().detail0 &&
            more_a.error().detail1 == more_b.error().detail1);
      return;
    }
    check(more_a.value() == more_b.value());
    if (!more_a.value()) return;
    check(a.number == b.number && a.timestamp_ns == b.timestamp_ns && a.link_type == b.link_type &&
          a.bytes.size() == b.bytes.size() && std::memcmp(a.bytes.data(), b.bytes.data(), a.bytes.size()) == 0);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rescue;        // NOLINT(google-build-using-namespace)
  using namespace rescue::ecat;  // NOLINT(google-build-using-namespace)
  auto reader = CaptureReader::open(ConstByteSpan(data, size));
  if (!reader.ok()) {
    check(reader.error().detail1 <= size);
    check_streamed_agrees(data, size);
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
  check_streamed_agrees(data, size);
  return 0;
}
