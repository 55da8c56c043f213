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
//    O_NOFOLLOW, so a link swapped after the check is refused, never followed;
//  - output files and the state directory: every directory on the path walked by descriptor, a link
//    on the way followed only when this user or root made it (open_trusted_directory below).
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

// Where files are written or trusted by name: every directory on the path, walked one component at a
// time relative to the descriptor of the one before (openat, O_NOFOLLOW), must pass the StrictModes
// rule, and a symbolic link on the way is followed only when this user or root owns it (another
// user's link in /tmp could point into our own 0700 directory). `output`: the directory of an output
// file (a root-owned sticky directory such as /tmp passes: nobody else can replace our entries);
// `state`: a directory whose entries are trusted by name, refused when group or others may create
// entries in it, sticky or not. Returns an O_PATH descriptor of the directory for create_regular_in.
enum class DirectoryUse { output, state };
Result<OpenFile> open_trusted_directory(const char* path, DirectoryUse use, FileProblem& why) noexcept;

// An output file `name` in `dir` (from open_trusted_directory; `dir_path` names it in messages):
// created with `mode` or truncated, never through a symbolic link (O_NOFOLLOW), never anything but a
// regular file of this user with one name (a hard link is refused: truncating it would empty the
// other name's file too).
Result<OpenFile> create_regular_in(const OpenFile& dir, const char* dir_path, const char* name, unsigned mode,
                                   FileProblem& why) noexcept;

// An output file (capture, timing output) by path: open_trusted_directory(its directory, output), then
// create_regular_in.
Result<OpenFile> open_regular_for_write(const char* path, unsigned mode, FileProblem& why) noexcept;

enum class Secrecy { public_file, secret };  // secret: also not readable by group or others

// open_regular_for_read after the StrictModes check of the file and every directory above it.
// permission_denied for an untrusted owner or mode.
Result<OpenFile> open_trusted_for_read(const char* path, Secrecy secrecy, FileProblem& why) noexcept;

// The state directory: open_trusted_directory(path, state) (a sticky directory everyone may write,
// such as /tmp itself, is refused: anyone could plant or lock its entries).
Status check_trusted_directory(const char* path, FileProblem& why) noexcept;

}  // namespace rescue::hal
