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
#include <utility>

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

// Whether a root-owned sticky directory writable by everyone (/tmp) passes: on the way to a file it
// does (nobody else can replace our entries there); as a directory whose entries we trust by name
// (the state directory) it does not (anyone may create a name we have not created yet).
enum class Sticky { accepted, refused };

// StrictModes' rule for one file or directory.
Status check_owner_and_mode(const char* path, const struct stat& st, const char* role, Secrecy secrecy,
                            FileProblem& why, Sticky sticky = Sticky::accepted) noexcept {
  const uid_t me = ::geteuid();
  if (st.st_uid != me && st.st_uid != 0) {
    set_problem(why, "%s %s is owned by uid %u, not by uid %u (this user) or root: refused (chown %u %s, or use a path of your own)",
        role, path, static_cast<unsigned>(st.st_uid), static_cast<unsigned>(me), static_cast<unsigned>(me), path);
    return make_error(Errc::permission_denied, "owned by another user", static_cast<std::uint32_t>(st.st_uid));
  }
  const bool sticky_root_dir =
      sticky == Sticky::accepted && S_ISDIR(st.st_mode) && (st.st_mode & S_ISVTX) != 0 && st.st_uid == 0;
  if (sticky == Sticky::refused && S_ISDIR(st.st_mode) && (st.st_mode & S_ISVTX) != 0 && (st.st_mode & 022U) != 0) {
    set_problem(why, "%s %s is shared: sticky and writable by group or others (mode %04o), so anyone may create or lock an entry before we do: refused (give a directory of your own)",
        role, path, static_cast<unsigned>(st.st_mode & 07777U));
    return make_error(Errc::permission_denied, "shared sticky directory", static_cast<std::uint32_t>(st.st_mode & 07777U));
  }
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


// `walked` + "/" + `name` into `walked` (for messages only: truncated to fit).
void append_component(std::array<char, PATH_MAX>& walked, const char* name) noexcept {
  const std::size_t n = std::strlen(walked.data());
  (void)std::snprintf(walked.data() + n, walked.size() - n, "%s%s", n > 0 && walked[n - 1] == '/' ? "" : "/", name);
}

// The walk of open_trusted_directory: `path` one component at a time, each looked up relative to the
// descriptor of the directory already checked, so nothing swapped after a check is followed.
Result<OpenFile> walk_directories(const char* path, DirectoryUse use, FileProblem& why) noexcept {
  constexpr int kMaxLinks = 40;  // the kernel's own limit (ELOOP)
  std::array<char, PATH_MAX> rest{};  // what is still to walk
  if (std::strlen(path) >= rest.size()) {
    set_problem(why, "%.200s...: path too long", path);
    return make_error(Errc::invalid_argument, "path too long");
  }
  std::memcpy(rest.data(), path, std::strlen(path) + 1);
  std::array<char, PATH_MAX> walked{};  // where the walk is, in words
  const bool absolute = path[0] == '/';
  if (absolute) {
    walked[0] = '/';
  } else {
    // A relative path starts at the working directory: it and every directory above it checked.
    if (::getcwd(walked.data(), walked.size()) == nullptr) return os_error(why, path, "find the working directory");
    RESCUE_TRY(check_directories(walked.data(), true, path, why));
  }
  OpenFile at(::open(absolute ? "/" : ".", O_PATH | O_DIRECTORY | O_CLOEXEC));  // NOLINT(cppcoreguidelines-pro-type-vararg)
  if (at.fd() < 0) return os_error(why, walked.data(), "open the directory");
  struct stat st {};
  if (::fstat(at.fd(), &st) != 0) return os_error(why, walked.data(), "examine the directory");
  RESCUE_TRY(check_owner_and_mode(walked.data(), st, "directory", Secrecy::public_file, why));
  std::size_t pos = 0;
  int links = 0;
  bool entered = false;  // whether `at` is the directory the path names (not merely the start)
  for (;;) {
    while (rest[pos] == '/') ++pos;
    if (rest[pos] == '\0') break;
    std::array<char, NAME_MAX + 1> name{};
    std::size_t n = 0;
    while (rest[pos] != '\0' && rest[pos] != '/') {
      if (n + 1 >= name.size()) {
        set_problem(why, "%s: a name in it is longer than %d bytes", path, NAME_MAX);
        return make_error(Errc::invalid_argument, "name too long");
      }
      name[n++] = rest[pos++];
    }
    if (std::strcmp(name.data(), ".") == 0) continue;
    struct stat entry {};
    if (::fstatat(at.fd(), name.data(), &entry, AT_SYMLINK_NOFOLLOW) != 0) {
      append_component(walked, name.data());
      return os_error(why, walked.data(), "examine it");
    }
    if (S_ISLNK(entry.st_mode)) {
      // Another user's link (in /tmp, say) redirects the path wherever they like, into our own
      // files too: followed only when made by this user or root, whatever fs.protected_symlinks says.
      if (entry.st_uid != ::geteuid() && entry.st_uid != 0) {
        append_component(walked, name.data());
        set_problem(why, "%s is a symbolic link owned by uid %u, not by this user (uid %u) or root: refused (give the path of the directory itself)",
            walked.data(), static_cast<unsigned>(entry.st_uid), static_cast<unsigned>(::geteuid()));
        return make_error(Errc::permission_denied, "another user's symbolic link", static_cast<std::uint32_t>(entry.st_uid));
      }
      if (++links > kMaxLinks) {
        set_problem(why, "%s: more than %d symbolic links", path, kMaxLinks);
        return make_error(Errc::invalid_argument, "too many symbolic links");
      }
      std::array<char, PATH_MAX> target{};
      const ssize_t t = ::readlinkat(at.fd(), name.data(), target.data(), target.size() - 1);
      if (t <= 0) return os_error(why, name.data(), "read the symbolic link");
      const std::size_t tail = std::strlen(rest.data() + pos);
      if (static_cast<std::size_t>(t) + 1 + tail >= rest.size()) {
        set_problem(why, "%s: path too long after following its links", path);
        return make_error(Errc::invalid_argument, "path too long");
      }
      // rest = target + "/" + what followed the link.
      std::memmove(rest.data() + t + 1, rest.data() + pos, tail + 1);
      std::memcpy(rest.data(), target.data(), static_cast<std::size_t>(t));
      rest[static_cast<std::size_t>(t)] = '/';
      pos = 0;
      if (target[0] == '/') {
        at = OpenFile(::open("/", O_PATH | O_DIRECTORY | O_CLOEXEC));  // NOLINT(cppcoreguidelines-pro-type-vararg)
        if (at.fd() < 0) return os_error(why, "/", "open the directory");
        walked = {};
        walked[0] = '/';
      }
      continue;
    }
    append_component(walked, name.data());
    OpenFile next(::openat(at.fd(), name.data(), O_PATH | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC));  // NOLINT(cppcoreguidelines-pro-type-vararg)
    if (next.fd() < 0) {
      if (errno == ENOTDIR) {
        set_problem(why, "%s is %s, not a directory", walked.data(), kind_of(entry.st_mode));
        return make_error(Errc::invalid_argument, "not a directory");
      }
      return os_error(why, walked.data(), "open the directory");
    }
    if (::fstat(next.fd(), &st) != 0) return os_error(why, walked.data(), "examine the directory");
    std::size_t after = pos;
    while (rest[after] == '/') ++after;
    const bool last = rest[after] == '\0';
    const Sticky sticky = last && use == DirectoryUse::state ? Sticky::refused : Sticky::accepted;
    RESCUE_TRY(check_owner_and_mode(walked.data(), st, last && use == DirectoryUse::state ? "state directory" : "directory",
                                    Secrecy::public_file, why, sticky));
    at = std::move(next);
    entered = true;
  }
  if (!entered && use == DirectoryUse::state) {  // "/" or "." itself, or a walk that ended on the start
    if (::fstat(at.fd(), &st) != 0) return os_error(why, walked.data(), "examine the directory");
    RESCUE_TRY(check_owner_and_mode(walked.data(), st, "state directory", Secrecy::public_file, why, Sticky::refused));
  }
  return at;
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

Result<OpenFile> open_trusted_directory(const char* path, DirectoryUse use, FileProblem& why) noexcept {
  if (path == nullptr || path[0] == '\0') {
    set_problem(why, "empty directory path");
    return make_error(Errc::invalid_argument, "empty path");
  }
  return walk_directories(path, use, why);
}

Result<OpenFile> create_regular_in(const OpenFile& dir, const char* dir_path, const char* name, unsigned mode,
                                   FileProblem& why) noexcept {
  std::array<char, PATH_MAX> shown{};  // the file's name in messages
  (void)std::snprintf(shown.data(), shown.size(), "%s%s%s", dir_path,
                      dir_path[0] != '\0' && dir_path[std::strlen(dir_path) - 1] != '/' ? "/" : "", name);
  if (name[0] == '\0' || std::strchr(name, '/') != nullptr || std::strcmp(name, ".") == 0 || std::strcmp(name, "..") == 0) {
    set_problem(why, "%s: not a file name", shown.data());
    return make_error(Errc::invalid_argument, "not a file name");
  }
  // No O_TRUNC here: a device or FIFO is refused before anything is truncated.
  const int fd = ::openat(dir.fd(), name, O_WRONLY | O_CREAT | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY | O_CLOEXEC,  // NOLINT(cppcoreguidelines-pro-type-vararg)
                          static_cast<mode_t>(mode));
  if (fd < 0) return open_failed(why, shown.data(), "create it");
  OpenFile file(fd);
  struct stat st {};
  if (::fstat(fd, &st) != 0) return os_error(why, shown.data(), "examine it");
  if (!S_ISREG(st.st_mode)) return not_regular(why, shown.data(), st.st_mode);
  if (st.st_uid != ::geteuid()) {
    set_problem(why, "%s exists and is owned by uid %u, not by this user (uid %u): refused (remove it or give another path)", shown.data(),
        static_cast<unsigned>(st.st_uid), static_cast<unsigned>(::geteuid()));
    return make_error(Errc::permission_denied, "owned by another user", static_cast<std::uint32_t>(st.st_uid));
  }
  if (st.st_nlink > 1) {  // a hard link: truncating it would empty the same file under another name
    set_problem(why, "%s has %u names (a hard link): refused (remove it or give another path)", shown.data(),
        static_cast<unsigned>(st.st_nlink));
    return make_error(Errc::permission_denied, "hard link", static_cast<std::uint32_t>(st.st_nlink));
  }
  if (::ftruncate(fd, 0) != 0) return os_error(why, shown.data(), "truncate it");
  const int fl = ::fcntl(fd, F_GETFL);  // NOLINT(cppcoreguidelines-pro-type-vararg)
  if (fl < 0 || ::fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) != 0) return os_error(why, shown.data(), "set blocking mode");  // NOLINT(cppcoreguidelines-pro-type-vararg)
  return file;
}

Result<OpenFile> open_regular_for_write(const char* path, unsigned mode, FileProblem& why) noexcept {
  std::array<char, PATH_MAX> dir{};
  if (std::strlen(path) >= dir.size()) {
    set_problem(why, "%.200s...: path too long", path);
    return make_error(Errc::invalid_argument, "path too long");
  }
  const char* slash = std::strrchr(path, '/');
  if (slash == nullptr) {
    dir[0] = '.';
  } else {
    const std::size_t n = slash == path ? 1 : static_cast<std::size_t>(slash - path);  // "/name": the root
    std::memcpy(dir.data(), path, n);
  }
  FileProblem inner;
  const Result<OpenFile> parent = open_trusted_directory(dir.data(), DirectoryUse::output, inner);
  if (!parent.ok()) {
    set_problem(why, "cannot create %s: %s", path, inner.c_str());  // the file, then what is wrong on its way
    return parent.error();
  }
  return create_regular_in(parent.value(), slash == nullptr ? "" : dir.data(), slash == nullptr ? path : slash + 1, mode, why);
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
  const Result<OpenFile> dir = open_trusted_directory(path, DirectoryUse::state, why);
  if (!dir.ok()) return dir.error();
  return Status::success();
}

}  // namespace rescue::hal
