// A whole regular file read once into private memory: tools hand its bytes to decoders (captures,
// SII images) without heap. The bytes are a copy (pread into an anonymous mapping), never a
// mapping of the file itself, so another process truncating or rewriting the file while it is read
// cannot raise SIGBUS or change bytes under the decoder: a file that shrinks during the read gives
// the bytes that were there (shrank() says so), one that grows gives its size at open.
//
// The file is opened non-blocking (a FIFO with no writer, a terminal or a device never hangs
// open()) and anything but a regular file is refused.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"

namespace rescue::hal {

class FileSnapshot {
 public:
  FileSnapshot() = default;
  ~FileSnapshot();
  FileSnapshot(const FileSnapshot&) = delete;
  FileSnapshot& operator=(const FileSnapshot&) = delete;
  FileSnapshot(FileSnapshot&& other) noexcept;
  FileSnapshot& operator=(FileSnapshot&& other) noexcept;

  // Reads `path`. An empty file gives an empty span. Errors: io_error "open file" / "stat file" /
  // "allocate" / "read file" with errno in detail0, invalid_argument "not a regular file".
  static Result<FileSnapshot> open(const char* path) noexcept;

  ConstByteSpan bytes() const noexcept { return {data_, size_}; }
  // The file was shorter at the end of the read than when it was opened.
  bool shrank() const noexcept { return shrank_; }

 private:
  void release() noexcept;

  std::uint8_t* data_{nullptr};
  std::size_t size_{0};
  std::size_t mapped_{0};  // length of the anonymous mapping (the size at open)
  bool shrank_{false};
};

}  // namespace rescue::hal
