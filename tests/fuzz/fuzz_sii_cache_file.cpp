// libFuzzer target: SiiCache::decode on arbitrary bytes must never read out of bounds; whatever it
// accepts encodes back to the same bytes, and every image it holds parses with its CRC checked.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "ecat/sii/sii.hpp"
#include "ecat/sii/sii_cache.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rescue::ecat;
  static SiiCache cache;
  static std::array<std::uint8_t, kSiiCacheFileMax> out{};
  if (!cache.decode(rescue::ConstByteSpan(data, size)).ok()) {
    if (cache.size() != 0) std::abort();
    return 0;
  }
  const auto encoded = cache.encode(rescue::ByteSpan(out));
  if (!encoded.ok() || encoded.value() != size || std::memcmp(out.data(), data, size) != 0) std::abort();
  return 0;
}
