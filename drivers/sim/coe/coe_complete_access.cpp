#include "drivers/sim/coe/coe_complete_access.hpp"

#include <array>
#include <cstring>

#include "ecat/mailbox/coe.hpp"

namespace rescue::drivers {
namespace {

namespace abort_code = ecat::coe::abort_code;

constexpr std::size_t kSubindex0Bytes = 2;  // UINT8 padded to 16 bits
constexpr std::size_t kMaxSubindexes = 256;

bool has_subindexes(const ObjectDictionary& od, std::uint16_t index) noexcept {
  return od.find(index, 1) != nullptr;
}

std::uint8_t entry_count(const ObjectDictionary& od, std::uint16_t index) noexcept {
  const ObjectRead r = od.read(index, 0);
  return r.abort_code == 0 && !r.bytes.empty() ? r.bytes[0] : 0;
}

// Bytes the entries 1..n take, or 0 when one of them is missing or not a fixed-size value.
std::size_t entries_size(const ObjectDictionary& od, std::uint16_t index, std::uint8_t n) noexcept {
  std::size_t total = 0;
  for (unsigned sub = 1; sub <= n; ++sub) {
    const ObjectEntry* e = od.find(index, static_cast<std::uint8_t>(sub));
    if (e == nullptr || e->size > 4) return 0;
    total += e->size;
  }
  return total;
}

}  // namespace

std::uint32_t read_complete(const ObjectDictionary& od, std::uint16_t index, std::uint8_t subindex, ByteSpan out,
                            std::size_t& length) noexcept {
  length = 0;
  if (od.find(index, 0) == nullptr) return abort_code::kObjectDoesNotExist;
  if (subindex > 1) return abort_code::kUnsupportedAccess;
  if (!has_subindexes(od, index)) {
    if (subindex != 0) return abort_code::kSubindexDoesNotExist;
    const ObjectRead r = od.read(index, 0);
    if (r.bytes.size() > out.size()) return abort_code::kOutOfMemory;
    std::memcpy(out.data(), r.bytes.data(), r.bytes.size());
    length = r.bytes.size();
    return 0;
  }
  const std::uint8_t n = entry_count(od, index);
  std::size_t at = 0;
  if (subindex == 0) {
    if (out.size() < kSubindex0Bytes) return abort_code::kOutOfMemory;
    out[0] = n;
    out[1] = 0;
    at = kSubindex0Bytes;
  }
  for (unsigned sub = 1; sub <= n; ++sub) {
    const ObjectEntry* e = od.find(index, static_cast<std::uint8_t>(sub));
    if (e == nullptr) return abort_code::kSubindexDoesNotExist;
    const ObjectRead r = od.read(index, static_cast<std::uint8_t>(sub));
    if (r.abort_code != 0) return r.abort_code;
    if (at + e->size > out.size()) return abort_code::kOutOfMemory;
    // Fixed layout: a value shorter than its entry (a string) is padded with zeros.
    std::memset(out.data() + at, 0, e->size);
    std::memcpy(out.data() + at, r.bytes.data(), r.bytes.size() < e->size ? r.bytes.size() : e->size);
    at += e->size;
  }
  length = at;
  return 0;
}

std::uint32_t write_complete(ObjectDictionary& od, std::uint16_t index, std::uint8_t subindex, ConstByteSpan data,
                             ecat::reg::AlState state) noexcept {
  if (od.find(index, 0) == nullptr) return abort_code::kObjectDoesNotExist;
  if (subindex > 1) return abort_code::kUnsupportedAccess;
  if (!has_subindexes(od, index)) {
    if (subindex != 0) return abort_code::kSubindexDoesNotExist;
    return od.write(index, 0, data, state);
  }
  const bool with_count = subindex == 0;
  if (with_count && data.size() < kSubindex0Bytes) return abort_code::kLengthTooLow;
  const std::uint8_t n = with_count ? data[0] : entry_count(od, index);
  const ConstByteSpan entries = with_count ? data.subspan(kSubindex0Bytes, data.size() - kSubindex0Bytes) : data;
  const std::size_t expected = entries_size(od, index, n);
  if (n > 0 && expected == 0) return od.find(index, n) == nullptr ? abort_code::kValueTooHigh : abort_code::kCompleteAccessUnsupported;
  if (entries.size() != expected) return entries.size() > expected ? abort_code::kLengthTooHigh : abort_code::kLengthTooLow;

  // What to put back when a write is refused half way.
  std::array<std::uint32_t, kMaxSubindexes> before{};
  for (unsigned sub = 0; sub <= n; ++sub) before[sub] = od.get_u32(index, static_cast<std::uint8_t>(sub));
  const auto restore = [&]() {
    for (unsigned sub = 0; sub <= n; ++sub) od.set(index, static_cast<std::uint8_t>(sub), before[sub]);
  };

  const std::uint8_t zero = 0;
  if (with_count) {
    const std::uint32_t code = od.write(index, 0, ConstByteSpan(&zero, 1), state);
    if (code != 0) return code;
  }
  std::size_t at = 0;
  for (unsigned sub = 1; sub <= n; ++sub) {
    const ObjectEntry* e = od.find(index, static_cast<std::uint8_t>(sub));
    const std::uint32_t code = od.write(index, static_cast<std::uint8_t>(sub), entries.subspan(at, e->size), state);
    if (code != 0) {
      restore();
      return code;
    }
    at += e->size;
  }
  if (with_count) {
    const std::uint32_t code = od.write(index, 0, ConstByteSpan(&n, 1), state);
    if (code != 0) {
      restore();
      return code;
    }
  }
  return 0;
}

}  // namespace rescue::drivers
