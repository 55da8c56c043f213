#include "hal/files/durable_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace rescue::hal {
namespace {

Error os_error(const char* what) noexcept {
  const int e = errno;
  if (e == ENOENT) return make_error(Errc::not_found, what, static_cast<std::uint32_t>(e));
  if (e == EACCES || e == EPERM || e == EROFS) return make_error(Errc::permission_denied, what, static_cast<std::uint32_t>(e));
  return make_error(Errc::io_error, what, static_cast<std::uint32_t>(e));
}

Status write_all(int fd, ConstByteSpan bytes) noexcept {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      return os_error("write temporary file");
    }
    done += static_cast<std::size_t>(n);
  }
  return Status::success();
}

Status fsync_directory(const char* dir) noexcept {
  const int fd = ::open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return os_error("open directory for fsync");
  const int rc = ::fsync(fd);
  const Error err = os_error("fsync directory");
  ::close(fd);
  if (rc != 0) return err;
  return Status::success();
}

// dir/name<suffix>: a file's temporary sibling.
Result<PathBuffer> sibling_path(const char* dir, const char* name, const char* suffix) noexcept {
  PathBuffer sibling;
  const int n = std::snprintf(sibling.text.data(), sibling.text.size(), "%s%s", name, suffix);
  if (n < 0 || static_cast<std::size_t>(n) >= sibling.text.size()) return make_error(Errc::out_of_range, "path too long");
  return join_path(dir, sibling.c_str());
}

// Whatever is at `path` (a file left by a writer that crashed, or a FIFO, a link, a directory entry
// someone put there) is removed, and the file created anew, exclusively: nothing there can block the
// open or redirect the write. Then written whole and fsynced. `exact_mode`: `mode` whatever the umask.
Status write_new_file(const char* path, ConstByteSpan contents, unsigned mode, bool exact_mode) noexcept {
  if (::unlink(path) != 0 && errno != ENOENT) return os_error("remove the old temporary file");
  const int fd = ::open(path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK, mode);
  if (fd < 0) return os_error("create temporary file");
  Status status = Status::success();
  if (exact_mode && ::fchmod(fd, mode) != 0) status = os_error("set the file's mode");
  if (status.ok()) status = write_all(fd, contents);
  if (status.ok() && ::fsync(fd) != 0) status = os_error("fsync temporary file");
  if (::close(fd) != 0 && status.ok()) status = os_error("close temporary file");
  return status;
}

// Renames `from` to `to` without replacing a file there: RENAME_NOREPLACE, or link + unlink where the
// filesystem lacks it. busy when `to` exists.
Status move_without_replacing(const char* from, const char* to) noexcept {
  if (::renameat2(AT_FDCWD, from, AT_FDCWD, to, RENAME_NOREPLACE) == 0) return Status::success();
  if (errno == EEXIST) return make_error(Errc::busy, "file already exists; not overwritten");
  if (errno != EINVAL && errno != ENOSYS) return os_error("rename without replacing");
  if (::link(from, to) != 0) {
    return errno == EEXIST ? make_error(Errc::busy, "file already exists; not overwritten") : os_error("link without replacing");
  }
  if (::unlink(from) != 0) return os_error("unlink after link");
  return Status::success();
}

}  // namespace

Result<PathBuffer> join_path(const char* dir, const char* name) noexcept {
  PathBuffer out;
  const int n = std::snprintf(out.text.data(), out.text.size(), "%s/%s", dir, name);
  if (n < 0 || static_cast<std::size_t>(n) >= out.text.size()) {
    return make_error(Errc::out_of_range, "path too long", static_cast<std::uint32_t>(n < 0 ? 0 : n));
  }
  return out;
}

Result<DirAndName> split_path(const char* path) noexcept {
  DirAndName out;
  const char* slash = std::strrchr(path, '/');
  out.name = slash != nullptr ? slash + 1 : path;
  if (*out.name == '\0') return make_error(Errc::invalid_argument, "path has no file name");
  const std::size_t dir_length = slash == nullptr ? 0 : (slash == path ? 1 : static_cast<std::size_t>(slash - path));
  if (dir_length >= out.dir.text.size()) return make_error(Errc::out_of_range, "path too long");
  if (dir_length == 0) {
    out.dir.text[0] = '.';
  } else {
    std::memcpy(out.dir.text.data(), path, dir_length);
  }
  return out;
}

Result<std::size_t> read_file_capped(const char* path, ByteSpan buffer) noexcept {
  // O_NONBLOCK: opening a FIFO someone left in place of the file must not hang start-up.
  const int fd = ::open(path, O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
  if (fd < 0) {
    const Error err = os_error("open file");
    struct stat link {};
    if (err.code == Errc::not_found && ::lstat(path, &link) == 0 && S_ISLNK(link.st_mode)) {
      return make_error(Errc::malformed, "symbolic link whose target does not exist");
    }
    return err;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const Error err = os_error("stat file");
    ::close(fd);
    return err;
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd);
    return make_error(Errc::malformed, "not a regular file");
  }
  const auto announced = static_cast<std::uint64_t>(st.st_size);
  if (announced > buffer.size()) {
    ::close(fd);
    return make_error(Errc::capacity_exceeded, "file larger than the read cap",
                      static_cast<std::uint32_t>(announced > 0xFFFFFFFFU ? 0xFFFFFFFFU : announced),
                      static_cast<std::uint32_t>(buffer.size()));
  }
  std::size_t got = 0;
  for (;;) {
    // The file may have grown since fstat: read one byte past the buffer to notice.
    std::uint8_t extra = 0;
    std::uint8_t* dst = got < buffer.size() ? buffer.data() + got : &extra;
    const std::size_t want = got < buffer.size() ? buffer.size() - got : 1;
    const ssize_t n = ::read(fd, dst, want);
    if (n < 0) {
      if (errno == EINTR) continue;
      const Error err = os_error("read file");
      ::close(fd);
      return err;
    }
    if (n == 0) break;
    if (got >= buffer.size()) {
      ::close(fd);
      return make_error(Errc::capacity_exceeded, "file larger than the read cap", static_cast<std::uint32_t>(got + 1),
                        static_cast<std::uint32_t>(buffer.size()));
    }
    got += static_cast<std::size_t>(n);
  }
  ::close(fd);
  return got;
}

Status write_file_atomically(const char* dir, const char* name, ConstByteSpan contents, DirectorySync sync) noexcept {
  auto target = join_path(dir, name);
  if (!target.ok()) return target.error();
  auto temp = sibling_path(dir, name, ".tmp");
  if (!temp.ok()) return temp.error();
  Status status = write_new_file(temp.value().c_str(), contents, 0644, false);
  if (status.ok() && ::rename(temp.value().c_str(), target.value().c_str()) != 0) status = os_error("rename over the file");
  if (!status.ok()) {
    (void)::unlink(temp.value().c_str());
    return status;
  }
  // The rename is atomic but lives in the directory: without this fsync a power cut could bring back
  // the old name after we reported success.
  return sync == DirectorySync::now ? fsync_directory(dir) : Status::success();
}

Status create_file_durably(const char* dir, const char* name, ConstByteSpan contents, unsigned mode) noexcept {
  auto target = join_path(dir, name);
  if (!target.ok()) return target.error();
  auto temp = sibling_path(dir, name, ".new");
  if (!temp.ok()) return temp.error();
  struct stat there {};
  if (::lstat(target.value().c_str(), &there) == 0) return make_error(Errc::busy, "file already exists; not overwritten");
  Status status = write_new_file(temp.value().c_str(), contents, mode, true);
  if (status.ok()) status = move_without_replacing(temp.value().c_str(), target.value().c_str());
  if (!status.ok()) {
    (void)::unlink(temp.value().c_str());
    return status;
  }
  return fsync_directory(dir);
}

Status rename_durably(const char* dir, const char* from, const char* to) noexcept {
  auto a = join_path(dir, from);
  if (!a.ok()) return a.error();
  auto b = join_path(dir, to);
  if (!b.ok()) return b.error();
  if (::rename(a.value().c_str(), b.value().c_str()) != 0) return os_error("rename");
  return fsync_directory(dir);
}

Result<std::uint32_t> set_aside_durably(const char* dir, const char* from, const char* base, std::uint32_t max_suffix) noexcept {
  auto source = join_path(dir, from);
  if (!source.ok()) return source.error();
  for (std::uint32_t suffix = 0; suffix <= max_suffix; ++suffix) {
    PathBuffer name;
    const int n = suffix == 0 ? std::snprintf(name.text.data(), name.text.size(), "%s", base)
                              : std::snprintf(name.text.data(), name.text.size(), "%s.%u", base, suffix);
    if (n < 0 || static_cast<std::size_t>(n) >= name.text.size()) return make_error(Errc::out_of_range, "path too long");
    auto target = join_path(dir, name.c_str());
    if (!target.ok()) return target.error();
    const Status moved = move_without_replacing(source.value().c_str(), target.value().c_str());
    if (!moved.ok() && moved.error().code == Errc::busy) continue;  // that name is taken: the next
    if (!moved.ok()) return moved.error();
    const Status synced = fsync_directory(dir);
    if (!synced.ok()) return synced.error();
    return suffix;
  }
  return make_error(Errc::capacity_exceeded, "every set-aside name is taken", max_suffix);
}

Status make_directories(const char* path, unsigned mode) noexcept {
  PathBuffer buf;
  const std::size_t len = std::strlen(path);
  if (len == 0) return make_error(Errc::invalid_argument, "empty directory path");
  if (len >= buf.text.size()) return make_error(Errc::out_of_range, "path too long", static_cast<std::uint32_t>(len));
  std::memcpy(buf.text.data(), path, len + 1);
  // Create each prefix in turn; an existing directory is fine.
  for (std::size_t i = 1; i <= len; ++i) {
    if (buf.text[i] != '/' && buf.text[i] != '\0') continue;
    const char saved = buf.text[i];
    buf.text[i] = '\0';
    if (::mkdir(buf.c_str(), static_cast<mode_t>(mode)) != 0 && errno != EEXIST) return os_error("create directory");
    buf.text[i] = saved;
  }
  struct stat st {};
  if (::stat(path, &st) != 0) return os_error("stat directory");
  if (!S_ISDIR(st.st_mode)) return make_error(Errc::invalid_argument, "exists and is not a directory");
  return Status::success();
}

}  // namespace rescue::hal
