#include "hal/files/trusted_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace rescue::hal {
namespace {

Error os_error(FileProblem& why, const char* path, const char* doing) noexcept {
  const int e = errno;
  char reason[64];
  // GNU strerror_r (thread-safe): returns the text, in `reason` or a static string.
  set_problem(why, "%s: cannot %s (%s)", path, doing, strerror_r(e, reason, sizeof reason));
  if (e == ENOENT) return make_error(Errc::not_found, "no such file", static_cast<std::uint32_t>(e));
  if (e == EACCES || e == EPERM) return make_error(Errc::permission_denied, "no permission", static_cast<std::uint32_t>(e));
  return make_error(Errc::io_error, "cannot open", static_cast<std::uint32_t>(e));
}

const char* kind_of(mode_t mode) noexcept {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISLNK(mode)) return "a symbolic link";
  return "not a regular file";
}

Error not_regular(FileProblem& why, const char* path, mode_t mode) noexcept {
  set_problem(why, "%s is %s, not a regular file (give the path of a regular file)", path, kind_of(mode));
  return make_error(Errc::invalid_argument, "not a regular file");
}

// StrictModes' rule for one file or directory.
Status check_owner_and_mode(const char* path, const struct stat& st, const char* role, Secrecy secrecy,
                            FileProblem& why) noexcept {
  const uid_t me = ::geteuid();
  if (st.st_uid != me && st.st_uid != 0) {
    set_problem(why, "%s %s is owned by uid %u, not by uid %u (this user) or root: refused (chown %u %s, or use a path of your own)",
        role, path, static_cast<unsigned>(st.st_uid), static_cast<unsigned>(me), static_cast<unsigned>(me), path);
    return make_error(Errc::permission_denied, "owned by another user", static_cast<std::uint32_t>(st.st_uid));
  }
  const bool sticky_root_dir = S_ISDIR(st.st_mode) && (st.st_mode & S_ISVTX) != 0 && st.st_uid == 0;
  if ((st.st_mode & 022U) != 0 && !sticky_root_dir) {
    set_problem(why, "%s %s is writable by group or others (mode %04o): refused (chmod go-w %s)", role, path,
        static_cast<unsigned>(st.st_mode & 07777U), path);
    return make_error(Errc::permission_denied, "writable by group or others", static_cast<std::uint32_t>(st.st_mode & 07777U));
  }
  if (secrecy == Secrecy::secret && (st.st_mode & 077U) != 0) {
    set_problem(why, "%s %s is readable by group or others (mode %04o): refused (chmod 600 it)", role, path,
        static_cast<unsigned>(st.st_mode & 07777U));
    return make_error(Errc::permission_denied, "readable by group or others", static_cast<std::uint32_t>(st.st_mode & 07777U));
  }
  return Status::success();
}

// One directory of the canonical path: the first `n` bytes of `canon`.
Status check_directory_prefix(const char* canon, std::size_t n, FileProblem& why) noexcept {
  std::array<char, PATH_MAX> prefix{};
  std::memcpy(prefix.data(), canon, n);
  prefix[n] = '\0';
  struct stat st {};
  if (::lstat(prefix.data(), &st) != 0) return os_error(why, prefix.data(), "examine the directory");
  if (!S_ISDIR(st.st_mode)) {
    set_problem(why, "%s is %s, not a directory", prefix.data(), kind_of(st.st_mode));
    return make_error(Errc::invalid_argument, "not a directory");
  }
  return check_owner_and_mode(prefix.data(), st, "directory", Secrecy::public_file, why);
}

// Every directory of the canonical path `canon` from / down: its parent's when `self` is false (a
// file), itself too when true (a directory).
Status check_directories(const char* canon, bool self, const char* given, FileProblem& why) noexcept {
  const std::size_t length = std::strlen(canon);
  if (length == 0 || length >= PATH_MAX || canon[0] != '/') {
    set_problem(why, "%s: the resolved path %s is not absolute", given, canon);
    return make_error(Errc::invalid_argument, "path not absolute");
  }
  std::size_t last = length;
  if (!self) {
    while (last > 0 && canon[last] != '/') --last;
  }
  RESCUE_TRY(check_directory_prefix(canon, 1, why));  // "/"
  for (std::size_t i = 1; i < last; ++i) {
    if (canon[i] == '/') RESCUE_TRY(check_directory_prefix(canon, i, why));
  }
  if (last > 1) RESCUE_TRY(check_directory_prefix(canon, last, why));
  return Status::success();
}

// A failed open() with O_NOFOLLOW | O_NONBLOCK: what was at the name, in words.
Error open_failed(FileProblem& why, const char* path, const char* doing) noexcept {
  if (errno == ELOOP) {
    set_problem(why, "%s is a symbolic link: refused (give the path of the file itself)", path);
    return make_error(Errc::permission_denied, "symbolic link");
  }
  if (errno == EISDIR) {
    set_problem(why, "%s is a directory, not a regular file (give the path of a regular file)", path);
    return make_error(Errc::invalid_argument, "not a regular file");
  }
  if (errno == ENXIO) {
    set_problem(why, "%s is a FIFO or socket without a reader, not a regular file (give the path of a regular file)", path);
    return make_error(Errc::invalid_argument, "not a regular file");
  }
  return os_error(why, path, doing);
}

Result<OpenFile> open_and_check(const char* path, int flags, FileProblem& why) noexcept {
  const int fd = ::open(path, flags | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);  // NOLINT(cppcoreguidelines-pro-type-vararg)
  if (fd < 0) return open_failed(why, path, "open it");
  OpenFile file(fd);
  struct stat st {};
  if (::fstat(fd, &st) != 0) return os_error(why, path, "examine it");
  if (!S_ISREG(st.st_mode)) return not_regular(why, path, st.st_mode);
  // A regular file never blocks: back to ordinary reads and writes.
  const int fl = ::fcntl(fd, F_GETFL);  // NOLINT(cppcoreguidelines-pro-type-vararg)
  if (fl < 0 || ::fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) != 0) return os_error(why, path, "set blocking mode");  // NOLINT(cppcoreguidelines-pro-type-vararg)
  return file;
}

}  // namespace

void set_problem(FileProblem& why, const char* format, ...) noexcept {  // NOLINT(cert-dcl50-cpp): printf-style, checked by its format attribute
  va_list args;
  va_start(args, format);
  (void)std::vsnprintf(why.text.data(), why.text.size(), format, args);  // NOLINT(clang-analyzer-valist.Uninitialized)
  va_end(args);
}

OpenFile& OpenFile::operator=(OpenFile&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) (void)::close(fd_);
    fd_ = other.release();
  }
  return *this;
}

OpenFile::~OpenFile() {
  if (fd_ >= 0) (void)::close(fd_);
}

Result<OpenFile> open_regular_for_read(const char* path, FileProblem& why) noexcept {
  return open_and_check(path, O_RDONLY, why);
}

Result<OpenFile> open_regular_for_write(const char* path, unsigned mode, FileProblem& why) noexcept {
  // No O_TRUNC here: a device or FIFO is refused before anything is truncated.
  const int fd = ::open(path, O_WRONLY | O_CREAT | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY | O_CLOEXEC,  // NOLINT(cppcoreguidelines-pro-type-vararg)
                        static_cast<mode_t>(mode));
  if (fd < 0) return open_failed(why, path, "create it");
  OpenFile file(fd);
  struct stat st {};
  if (::fstat(fd, &st) != 0) return os_error(why, path, "examine it");
  if (!S_ISREG(st.st_mode)) return not_regular(why, path, st.st_mode);
  if (st.st_uid != ::geteuid()) {
    set_problem(why, "%s exists and is owned by uid %u, not by this user (uid %u): refused (remove it or give another path)", path,
        static_cast<unsigned>(st.st_uid), static_cast<unsigned>(::geteuid()));
    return make_error(Errc::permission_denied, "owned by another user", static_cast<std::uint32_t>(st.st_uid));
  }
  if (::ftruncate(fd, 0) != 0) return os_error(why, path, "truncate it");
  const int fl = ::fcntl(fd, F_GETFL);  // NOLINT(cppcoreguidelines-pro-type-vararg)
  if (fl < 0 || ::fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) != 0) return os_error(why, path, "set blocking mode");  // NOLINT(cppcoreguidelines-pro-type-vararg)
  return file;
}

Result<OpenFile> open_trusted_for_read(const char* path, Secrecy secrecy, FileProblem& why) noexcept {
  std::array<char, PATH_MAX> canon{};
  if (::realpath(path, canon.data()) == nullptr) {
    struct stat link {};
    if (errno == ENOENT && ::lstat(path, &link) == 0 && S_ISLNK(link.st_mode)) {
      set_problem(why, "%s is a symbolic link whose target does not exist", path);
      return make_error(Errc::not_found, "dangling symbolic link");
    }
    return os_error(why, path, "resolve its path");
  }
  RESCUE_TRY(check_directories(canon.data(), false, path, why));
  Result<OpenFile> file = open_and_check(canon.data(), O_RDONLY | O_NOFOLLOW, why);
  if (!file.ok()) return file.error();
  struct stat st {};
  if (::fstat(file.value().fd(), &st) != 0) return os_error(why, canon.data(), "examine it");
  const bool followed = std::strcmp(canon.data(), path) != 0;
  FileProblem inner;
  const Status trusted = check_owner_and_mode(canon.data(), st, followed ? "file (the target of the link)" : "file", secrecy, inner);
  if (!trusted.ok()) {
    if (followed) {
      set_problem(why, "%s -> %s", path, inner.c_str());
    } else {
      why = inner;
    }
    return trusted.error();
  }
  return file;
}

Status check_trusted_directory(const char* path, FileProblem& why) noexcept {
  std::array<char, PATH_MAX> canon{};
  if (::realpath(path, canon.data()) == nullptr) return os_error(why, path, "resolve its path");
  struct stat st {};
  if (::stat(canon.data(), &st) != 0) return os_error(why, canon.data(), "examine it");
  if (!S_ISDIR(st.st_mode)) {
    set_problem(why, "%s is %s, not a directory", path, kind_of(st.st_mode));
    return make_error(Errc::invalid_argument, "not a directory");
  }
  return check_directories(canon.data(), true, path, why);
}

}  // namespace rescue::hal
