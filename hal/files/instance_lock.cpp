#include "hal/files/instance_lock.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/file.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "hal/files/durable_file.hpp"

namespace rescue::hal {
namespace {

std::uint32_t errno_u32() noexcept { return static_cast<std::uint32_t>(errno); }

// The pid written in the lock file, 0 when unreadable.
std::uint32_t read_pid(int fd) noexcept {
  char text[32] = {};
  const ssize_t n = ::pread(fd, text, sizeof text - 1, 0);
  if (n <= 0) return 0;
  char* end = nullptr;
  const unsigned long pid = std::strtoul(text, &end, 10);
  return end != text && pid <= 0xFFFFFFFFUL ? static_cast<std::uint32_t>(pid) : 0;
}

}  // namespace

Status lock_state_directory(const char* dir) noexcept {
  auto path = join_path(dir, kStateLockName);
  if (!path.ok()) return path.error();
  // O_NONBLOCK, O_NOFOLLOW and fstat: a FIFO, a device or a link at the lock's name is refused, never waited on.
  const int fd = ::open(path.value().c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY, 0644);
  if (fd < 0) {
    const std::uint32_t e = errno_u32();
    return make_error(e == EACCES || e == EROFS ? Errc::permission_denied : Errc::io_error, "cannot open the lock file", e);
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    return make_error(Errc::invalid_argument, "the lock file is not a regular file");
  }
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const std::uint32_t e = errno_u32();
    const std::uint32_t holder = e == EWOULDBLOCK ? read_pid(fd) : 0;
    ::close(fd);
    if (e == EWOULDBLOCK) return make_error(Errc::busy, "state directory in use by another rescue-motion", holder);
    return make_error(Errc::io_error, "cannot lock the state directory", e);
  }
  // Ours: the pid, for the next one to name. The descriptor stays open until the process exits.
  char text[32];
  const int n = std::snprintf(text, sizeof text, "%ld\n", static_cast<long>(::getpid()));
  const bool pid_written = ::ftruncate(fd, 0) == 0 && n > 0 && ::pwrite(fd, text, static_cast<std::size_t>(n), 0) == n;
  (void)pid_written;  // without it the lock still holds; a second instance then names pid 0 ("unknown")
  return Status::success();
}

Status lock_raw_interface(const char* iface) noexcept {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  // Abstract name: a leading NUL, then the text (not NUL-terminated; its length is the address length).
  const int n = std::snprintf(address.sun_path + 1, sizeof address.sun_path - 1, "rescue-motion/nic/%s", iface);
  if (n <= 0 || static_cast<std::size_t>(n) >= sizeof address.sun_path - 1) {
    return make_error(Errc::out_of_range, "interface name too long for its lock");
  }
  const auto length = static_cast<socklen_t>(sizeof address.sun_family + 1 + static_cast<std::size_t>(n));
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return make_error(Errc::io_error, "cannot create the interface lock socket", errno_u32());
  // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the sockets API takes sockaddr*
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&address), length) == 0 && ::listen(fd, 4) == 0) {
    return Status::success();  // held until the process exits
  }
  const std::uint32_t e = errno_u32();
  ::close(fd);
  if (e != EADDRINUSE) return make_error(Errc::io_error, "cannot take the interface lock", e);
  // Taken: ask the holder who it is.
  std::uint32_t holder = 0;
  const int probe = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the sockets API takes sockaddr*
  if (probe >= 0 && ::connect(probe, reinterpret_cast<const sockaddr*>(&address), length) == 0) {
    ucred credentials{};
    socklen_t size = sizeof credentials;
    if (::getsockopt(probe, SOL_SOCKET, SO_PEERCRED, &credentials, &size) == 0) {
      holder = static_cast<std::uint32_t>(credentials.pid);
    }
  }
  if (probe >= 0) ::close(probe);
  return make_error(Errc::busy, "interface in use by another rescue-motion", holder);
}

}  // namespace rescue::hal
