// libFuzzer target: the redundant link's merge (ecat/link/redundant_merge.hpp) on arbitrary returned
// copies never reads or writes outside them: the input is a frame "sent" and two "copies" (split by
// two length bytes); whatever merge_copies accepts has the sent frame's datagrams, and each merged
// working counter is the sum of the copies' (saturated). make_ring_copy of any parseable frame
// parses again with the same datagram lengths.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "ecat/link/redundant_merge.hpp"

namespace {

using namespace rescue;        // NOLINT(google-build-using-namespace)
using namespace rescue::ecat;  // NOLINT(google-build-using-namespace)

void check(bool condition) {
  if (!condition) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::size_t rest = size - 2;
  const std::size_t a = rest == 0 ? 0 : data[0] * rest / 256;
  const std::size_t b = a + (rest - a == 0 ? 0 : data[1] * (rest - a) / 256);
  const ConstByteSpan sent_bytes(data + 2, a);
  const ConstByteSpan main_bytes(data + 2 + a, b - a);
  const ConstByteSpan ring_bytes(data + 2 + b, rest - b);
  const Result<FrameView> sent = FrameView::parse(sent_bytes);
  if (!sent.ok()) return 0;

  static std::array<std::uint8_t, kMaxFrameSize + kVlanTagSize + 4> ring_copy{};
  const Result<std::size_t> copied = make_ring_copy(sent_bytes, ByteSpan(ring_copy));
  if (copied.ok()) {
    const Result<FrameView> again = FrameView::parse(ConstByteSpan(ring_copy.data(), copied.value()));
    check(again.ok() && again.value().datagram_count() == sent.value().datagram_count());
    check(is_ring_copy(ConstByteSpan(ring_copy.data(), copied.value())));
  }

  static std::array<std::uint8_t, kMaxFrameSize + kVlanTagSize + 4> repeat{};
  constexpr std::uint8_t kRepeatIndex = 0x5A;
  const Result<std::size_t> repeated = make_repeat(sent_bytes, ByteSpan(repeat), kRepeatIndex);
  if (repeated.ok() && repeated.value() != 0) {
    const Result<FrameView> again = FrameView::parse(ConstByteSpan(repeat.data(), repeated.value()));
    check(again.ok() && again.value().datagram_count() == sent.value().datagram_count());
    for (const DatagramView d : again.value()) {
      check(d.index() == kRepeatIndex && (d.command() == Command::NOP || repeatable(d.command())));
    }
  }

  const Result<FrameView> main_copy = FrameView::parse(main_bytes);
  const Result<FrameView> ring = FrameView::parse(ring_bytes);
  static std::array<std::uint8_t, kMaxFrameSize + kVlanTagSize + 4> out{};
  static CopyCounters counters{};
  const Result<FrameView> merged = merge_copies(sent.value(), main_copy.ok() ? &main_copy.value() : nullptr,
                                                ring.ok() ? &ring.value() : nullptr, ByteSpan(out), counters);
  if (!merged.ok()) return 0;
  check(merged.value().datagram_count() == sent.value().datagram_count());
  std::size_t i = 0;
  for (const DatagramView d : merged.value()) {
    const std::uint32_t sum = std::uint32_t{counters.main[i]} + counters.ring[i];
    check(d.wkc() == (sum > 0xFFFFU ? 0xFFFFU : sum));
    ++i;
  }
  if (ring.ok()) {  // the ring copy standing for a repeat's merge
    CopyCounters repeat_counters = counters;
    repeat_counters.datagrams = ring.value().datagram_count();
    CopyCounters taken = counters;
    const ByteSpan merged_bytes(out.data(), merged.value().bytes().size());
    if (take_repeated(ring.value(), repeat_counters, merged_bytes, taken).ok()) {
      check(FrameView::parse(ConstByteSpan(merged_bytes.data(), merged_bytes.size())).ok());
    }
  }
  return 0;
}
