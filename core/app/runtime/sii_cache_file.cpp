#include "core/app/runtime/sii_cache_file.hpp"

#include <array>
#include <cstdint>

#include "hal/files/durable_file.hpp"

namespace rescue::app {
namespace {

// Start-up only, one thread: the file's bytes in static storage (no heap, no big stack frame).
std::array<std::uint8_t, ecat::kSiiCacheFileMax> g_file{};

}  // namespace

Status load_sii_cache(const char* dir, ecat::SiiCache& cache) noexcept {
  cache.clear();
  const Result<hal::PathBuffer> path = hal::join_path(dir, kSiiCacheFileName);
  if (!path.ok()) return path.error();
  const Result<std::size_t> read = hal::read_file_capped(path.value().c_str(), ByteSpan(g_file));
  if (!read.ok()) return read.error();
  return cache.decode(ConstByteSpan(g_file.data(), read.value()));
}

Status save_sii_cache(const char* dir, const ecat::SiiCache& cache) noexcept {
  const Result<std::size_t> encoded = cache.encode(ByteSpan(g_file));
  if (!encoded.ok()) return encoded.error();
  return hal::write_file_atomically(dir, kSiiCacheFileName, ConstByteSpan(g_file.data(), encoded.value()));
}

}  // namespace rescue::app
