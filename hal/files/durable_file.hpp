// Files that must survive a crash or a power cut (the error-joints file). Replacing a file is atomic
// and durable: write a temporary file in the same directory, fsync it, rename it over the old one,
// fsync the directory. At every instant the directory holds either the complete old file or the
// complete new one (POSIX rename is atomic; the fsyncs order the data before the name on disk).
// Reading is capped: a file bigger than the caller's buffer is refused, never read into memory.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"

namespace rescue::hal {

constexpr std::size_t kMaxPathLength = 512;

// A path in fixed storage (no heap); always NUL-terminated.
struct PathBuffer {
  std::array<char, kMaxPathLength> text{};
  const char* c_str() const noexcept { return text.data(); }
};

// "dir/name"; out_of_range when it does not fit.
Result<PathBuffer> join_path(const char* dir, const char* name) noexcept;

// The other way round: `path`'s directory ("." when it has none, "/" for a name in the root) and its
// last component (a pointer into `path`). invalid_argument for an empty path or one ending in '/';
// out_of_range when the directory does not fit.
struct DirAndName {
  PathBuffer dir;
  const char* name{nullptr};
};
Result<DirAndName> split_path(const char* path) noexcept;

// Reads the whole regular file at `path` into `buffer` and returns its size. Errors: not_found (nothing
// at `path`), malformed for a symbolic link whose target does not exist (it is reported, never taken for
// "no file") and for a file that is not a regular file (a FIFO or device would block or never end), capacity_exceeded
// when the file is larger than the buffer (detail0 = its size, saturated; nothing beyond the buffer is
// read), io_error (detail0 = errno).
Result<std::size_t> read_file_capped(const char* path, ByteSpan buffer) noexcept;

// Atomically and durably replaces dir/name with `contents` (through dir/name.tmp; one writer per file).
// Success means the new file and its directory entry have been fsynced. On failure dir/name is
// untouched (old contents) and the temporary file is removed.
// `later`: the directory is not fsynced here; the caller's next write_file_atomically(..., now) in the
// same directory makes this rename durable too (one directory fsync for two files).
enum class DirectorySync { now, later };
Status write_file_atomically(const char* dir, const char* name, ConstByteSpan contents,
                             DirectorySync sync = DirectorySync::now) noexcept;

// Creates dir/name with `contents` and `mode`, never replacing a file already there: through
// dir/name.new (removed first if a killed writer left it), fsynced, then renamed to dir/name with
// RENAME_NOREPLACE (link + unlink where the filesystem lacks it) and the directory fsynced. At every
// instant dir/name is absent or complete; success means both the file and its name are on disk.
// busy when dir/name exists (nothing written); on any failure dir/name is not created.
Status create_file_durably(const char* dir, const char* name, ConstByteSpan contents, unsigned mode) noexcept;

// Renames dir/from to dir/to (replacing it) and fsyncs the directory: keeps a file aside for
// post-mortem before a new one takes its name.
Status rename_durably(const char* dir, const char* from, const char* to) noexcept;

// Renames dir/from to the first free name of dir/base, dir/base.1, ... dir/base.<max_suffix>, never
// replacing a file already there (each set-aside keeps its own name), and fsyncs the directory.
// Returns the suffix used (0: `base` itself); capacity_exceeded when every name is taken.
Result<std::uint32_t> set_aside_durably(const char* dir, const char* from, const char* base, std::uint32_t max_suffix) noexcept;

// mkdir -p with `mode` for the directories it creates; success if `path` already is a directory.
Status make_directories(const char* path, unsigned mode) noexcept;

}  // namespace rescue::hal
