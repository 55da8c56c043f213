// The SII cache of `run` (ecat/sii/sii_cache.hpp) in the state directory, file `sii-cache`: loaded
// before bring-up, written back (atomically and durably) after it when bring-up read an image that
// was not in it. A missing file is an empty cache; a file that fails any check is reported and
// ignored (every slave's SII is read whole, and the next bring-up writes a good file).
#pragma once

#include "core/base/result.hpp"
#include "ecat/sii/sii_cache.hpp"

namespace rescue::app {

constexpr const char* kSiiCacheFileName = "sii-cache";

// Fills `cache` from dir/sii-cache. not_found when there is no file (the cache is empty then).
Status load_sii_cache(const char* dir, ecat::SiiCache& cache) noexcept;
// Writes `cache` to dir/sii-cache.
Status save_sii_cache(const char* dir, const ecat::SiiCache& cache) noexcept;

}  // namespace rescue::app
