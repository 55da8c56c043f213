#include "ecat/sii/sii_cache.hpp"

#include <algorithm>
#include <cstring>

#include "core/base/crc32.hpp"
#include "core/base/le_stream.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/sii/sii.hpp"

namespace rescue::ecat {
namespace {

constexpr std::array<std::uint8_t, 8> kMagic{'R', 'M', 'S', 'I', 'I', 'C', '0', '1'};
constexpr std::size_t kSerialOffset = std::size_t{2} * sii::kSerial;
// Vendor id, product code, revision, serial: words 8..15, what tells one device's EEPROM from another's.
constexpr std::size_t kIdentityOffset = std::size_t{2} * sii::kVendorId;
constexpr std::size_t kIdentityLength = kSiiIdentityBytes - kIdentityOffset;

bool has_serial(ConstByteSpan head) noexcept {
  return head.size() >= kSiiIdentityBytes && load_le32(head.data() + kSerialOffset) != 0;
}

bool same_head(const SiiImage& entry, ConstByteSpan head) noexcept {
  return std::memcmp(entry.bytes.data(), head.data(), kSiiIdentityBytes) == 0;
}

bool same_identity(const SiiImage& entry, const SiiImage& image) noexcept {
  return std::memcmp(entry.bytes.data() + kIdentityOffset, image.bytes.data() + kIdentityOffset, kIdentityLength) == 0;
}

// What the cache holds: a complete image, at least the identity long, with a serial number, that
// parses with its configuration CRC checked.
bool cacheable(ConstByteSpan bytes) noexcept {
  return has_serial(bytes) && sii::Sii::parse(bytes, sii::ChecksumPolicy::require).ok();
}

}  // namespace

const SiiImage* SiiCache::find(ConstByteSpan head) const noexcept {
  if (!has_serial(head)) return nullptr;
  for (std::size_t i = 0; i < count_; ++i) {
    if (same_head(entries_[i], head)) return &entries_[i];
  }
  return nullptr;
}

bool SiiCache::remember(const SiiImage& image) noexcept {
  if (image.error.code != Errc::ok || !image.complete || image.truncated || image.size < kSiiIdentityBytes) return false;
  if (!cacheable(image.view())) return false;
  std::size_t slot = count_;
  for (std::size_t i = 0; i < count_; ++i) {
    if (same_identity(entries_[i], image)) slot = i;
  }
  if (slot == count_) {
    if (count_ == entries_.size()) return false;
    ++count_;
  } else if (entries_[slot].size == image.size && std::memcmp(entries_[slot].bytes.data(), image.bytes.data(), image.size) == 0) {
    return true;  // the same image: nothing changed
  }
  SiiImage& entry = entries_[slot];
  entry = SiiImage{};
  std::memcpy(entry.bytes.data(), image.bytes.data(), image.size);
  entry.size = image.size;
  entry.complete = true;
  changed_ = true;
  return true;
}

void SiiCache::clear() noexcept {
  count_ = 0;
  changed_ = false;
}

Result<std::size_t> SiiCache::encode(ByteSpan out) const noexcept {
  LeWriter w(out);
  w.bytes(kMagic.data(), kMagic.size());
  w.u32(static_cast<std::uint32_t>(count_));
  for (std::size_t i = 0; i < count_; ++i) {
    const SiiImage& e = entries_[i];
    w.u16(e.size);
    w.bytes(e.bytes.data(), e.size);
    w.u32(crc32(e.view()));
  }
  if (!w.ok()) return make_error(Errc::capacity_exceeded, "SII cache file buffer too small", static_cast<std::uint32_t>(out.size()));
  const std::size_t body = w.size();
  w.u32(crc32(ConstByteSpan(out.data(), body)));
  if (!w.ok()) return make_error(Errc::capacity_exceeded, "SII cache file buffer too small", static_cast<std::uint32_t>(out.size()));
  return w.size();
}

Status SiiCache::decode(ConstByteSpan in) noexcept {
  clear();
  const auto refuse = [this](const char* what, std::size_t at) noexcept -> Status {
    clear();
    return make_error(Errc::invalid_argument, what, static_cast<std::uint32_t>(at));
  };
  if (in.size() < kMagic.size() + 8) return refuse("SII cache file: too short", in.size());
  const std::size_t body = in.size() - 4;
  if (crc32(ConstByteSpan(in.data(), body)) != load_le32(in.data() + body)) return refuse("SII cache file: CRC-32 of the file", body);
  if (std::memcmp(in.data(), kMagic.data(), kMagic.size()) != 0) return refuse("SII cache file: magic", 0);
  LeReader r(ConstByteSpan(in.data(), body));
  std::array<char, kMagic.size()> magic{};  // checked above
  r.chars(magic.data(), magic.size());
  const std::uint32_t count = r.u32();
  if (count > kSiiCacheCapacity) return refuse("SII cache file: more entries than the cache holds", kMagic.size());
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::size_t at = r.size();
    const std::uint16_t image_size = r.u16();
    if (!r.ok() || image_size < kSiiIdentityBytes || image_size > kSiiImageCapacity || body - r.size() < std::size_t{image_size} + 4) {
      return refuse("SII cache file: entry size", at);
    }
    SiiImage& e = entries_[count_];
    e = SiiImage{};
    r.chars(reinterpret_cast<char*>(e.bytes.data()), image_size);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): bytes as bytes
    e.size = image_size;
    e.complete = true;
    if (r.u32() != crc32(e.view())) return refuse("SII cache file: entry CRC-32", at);
    if (!cacheable(e.view())) return refuse("SII cache file: entry is not a valid SII image with a serial number", at);
    ++count_;
  }
  if (!r.ok() || r.size() != body) return refuse("SII cache file: bytes after the last entry", r.size());
  changed_ = false;
  return Status::success();
}

}  // namespace rescue::ecat
