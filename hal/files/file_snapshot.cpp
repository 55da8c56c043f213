#include "hal/files/file_snapshot.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <utility>

namespace rescue::hal {
namespace {

Error errno_error(const char* what, int fd) noexcept {
  const int error = errno;
  (void)::close(fd);
  return make_error(Errc::io_error, what, static_cast<std::uint32_t>(error));
}

}  // namespace

FileSnapshot::~FileSnapshot() { release(); }

FileSnapshot::FileSnapshot(FileSnapshot&& other) noexcept
    : data_(std::exchange(other.data_, nullptr)),
      size_(std::exchange(other.size_, 0)),
      mapped_(std::exchange(other.mapped_, 0)),
      shrank_(std::exchange(other.shrank_, false)) {}

FileSnapshot& FileSnapshot::operator=(FileSnapshot&& other) noexcept {
  if (this != &other) {
    release();
    data_ = std::exchange(other.data_, nullptr);
    size_ = std::exchange(other.size_, 0);
    mapped_ = std::exchange(other.mapped_, 0);
    shrank_ = std::exchange(other.shrank_, false);
  }
  return *this;
}

Result<FileSnapshot> FileSnapshot::open(const char* path) noexcept {
  // O_NONBLOCK: opening a FIFO without a writer (or a tty, a device) returns at once.
  const int fd = ::open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);  // NOLINT(cppcoreguidelines-pro-type-vararg)
  if (fd < 0) return make_error(Errc::io_error, "open file", static_cast<std::uint32_t>(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0) return errno_error("stat file", fd);
  if (!S_ISREG(st.st_mode)) {
    (void)::close(fd);
    return make_error(Errc::invalid_argument, "not a regular file");
  }
  FileSnapshot file;
  if (st.st_size <= 0) {
    (void)::close(fd);
    return file;
  }
  const auto size = static_cast<std::size_t>(st.st_size);
  void* p = ::mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) return errno_error("allocate", fd);  // NOLINT(cppcoreguidelines-pro-type-cstyle-cast): the libc macro
  file.data_ = static_cast<std::uint8_t*>(p);
  file.mapped_ = size;
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::pread(fd, file.data_ + done, size - done, static_cast<off_t>(done));
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN) continue;  // a regular file never blocks; a signal may interrupt
      return errno_error("read file", fd);            // `file` unmaps its memory on the way out
    }
    if (n == 0) {  // the file was truncated while we read it: keep what was there
      file.shrank_ = true;
      break;
    }
    done += static_cast<std::size_t>(n);
  }
  file.size_ = done;
  (void)::close(fd);
  return file;
}

void FileSnapshot::release() noexcept {
  if (data_ != nullptr) {
    (void)::munmap(data_, mapped_);
    data_ = nullptr;
    size_ = 0;
    mapped_ = 0;
    shrank_ = false;
  }
}

}  // namespace rescue::hal
