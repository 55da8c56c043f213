// A whole file mapped read-only into memory: tools hand its bytes to decoders (captures, SII
// images) without copying them and without heap. Unmapped when the object goes away.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"

namespace rescue::hal {

class MappedFile {
 public:
  MappedFile() = default;
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  MappedFile(MappedFile&& other) noexcept;
  MappedFile& operator=(MappedFile&& other) noexcept;

  // Maps `path`. An empty file maps to an empty span. Errors: io_error "open file" / "stat file" /
  // "map file" with errno in detail0, invalid_argument "not a regular file".
  static Result<MappedFile> open(const char* path) noexcept;

  ConstByteSpan bytes() const noexcept { return {data_, size_}; }

 private:
  void release() noexcept;

  const std::uint8_t* data_{nullptr};
  std::size_t size_{0};
};

}  // namespace rescue::hal
