// Files the program opens by name (key, configuration, capture, timing output, state files, decode
// inputs), opened so that nothing found at that name can hang the program or lead it into another
// user's place (docs/security.md):
//  - regular files only: opened with O_NONBLOCK (a FIFO without a writer, a tty or a device returns
//    at once), checked with fstat before a byte is read or written, refused naming what was found;
//  - trusted files (key, configuration) and the state directory as OpenSSH's StrictModes: the file
//    and every directory above it owned by this user or root and not writable by group or others
//    (a root-owned sticky directory such as /tmp is accepted: nobody else can replace our entries
//    there). A symbolic link is followed only to a target that passes the same check: the path is
//    resolved first (realpath), every directory of the result checked, and the result opened with
//    O_NOFOLLOW, so a link swapped after the check is refused, never followed.
// Every refusal is one sentence in a FileProblem naming the path, what is wrong and the fix.
#pragma once

#include <array>
#include <cstddef>

#include "core/base/result.hpp"

namespace rescue::hal {

struct FileProblem {
  std::array<char, 768> text{};
  const char* c_str() const noexcept { return text.data(); }
};

// printf into `why` (truncated to fit).
__attribute__((format(printf, 2, 3))) void set_problem(FileProblem& why, const char* format, ...) noexcept;

// An open file descriptor (closed on destruction); -1 when none.
class OpenFile {
 public:
  OpenFile() noexcept = default;
  explicit OpenFile(int fd) noexcept : fd_(fd) {}
  OpenFile(const OpenFile&) = delete;
  OpenFile& operator=(const OpenFile&) = delete;
  OpenFile(OpenFile&& other) noexcept : fd_(other.release()) {}
  OpenFile& operator=(OpenFile&& other) noexcept;
  ~OpenFile();
  int fd() const noexcept { return fd_; }
  int release() noexcept {
    const int taken = fd_;
    fd_ = -1;
    return taken;
  }

 private:
  int fd_{-1};
};

// Read-only, blocking reads afterwards. Errors (with `why` filled): not_found, permission_denied,
// invalid_argument (not a regular file: a FIFO, a directory, a device, a socket), io_error.
Result<OpenFile> open_regular_for_read(const char* path, FileProblem& why) noexcept;

// An output file (capture, timing output): created with `mode` or truncated, never through a
// symbolic link (O_NOFOLLOW) and never anything but a regular file.
Result<OpenFile> open_regular_for_write(const char* path, unsigned mode, FileProblem& why) noexcept;

enum class Secrecy { public_file, secret };  // secret: also not readable by group or others

// open_regular_for_read after the StrictModes check of the file and every directory above it.
// permission_denied for an untrusted owner or mode.
Result<OpenFile> open_trusted_for_read(const char* path, Secrecy secrecy, FileProblem& why) noexcept;

// The StrictModes check of a directory and every directory above it.
Status check_trusted_directory(const char* path, FileProblem& why) noexcept;

}  // namespace rescue::hal
