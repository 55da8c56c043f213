#include "hal/shm/shared_memory.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace rescue::hal {
namespace {

Error os_error(const char* what, int err) noexcept {
  const Errc code = (err == EACCES || err == EPERM) ? Errc::permission_denied : Errc::io_error;
  return make_error(code, what, static_cast<std::uint32_t>(err));
}

// Maps `fd` (closed here in every case) of `size` bytes.
Result<void*> map_and_close(int fd, std::size_t size) noexcept {
  void* data = ::mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  const int err = errno;
  (void)::close(fd);
  if (data == MAP_FAILED) return os_error("mmap shared memory", err);
  return data;
}

// The owner of the segment at `name` when this process may not even open it (Linux keeps POSIX
// shared memory in /dev/shm): for the refusal's message. 0xFFFFFFFF when unknown.
std::uint32_t owner_without_opening(const char* name) noexcept {
  char path[SharedMemory::kMaxNameLength + 16];
  (void)std::snprintf(path, sizeof path, "/dev/shm%s", name);
  struct stat st {};
  return ::lstat(path, &st) == 0 ? static_cast<std::uint32_t>(st.st_uid) : 0xFFFFFFFFU;
}

}  // namespace

bool valid_shared_memory_name(const char* name) noexcept {
  if (name == nullptr || name[0] != '/' || name[1] == '\0') return false;
  const std::size_t length = std::strlen(name);
  if (length >= SharedMemory::kMaxNameLength) return false;
  return std::strchr(name + 1, '/') == nullptr;
}

SharedMemory::~SharedMemory() { release(); }

SharedMemory::SharedMemory(SharedMemory&& other) noexcept : data_(other.data_), size_(other.size_) {
  other.data_ = nullptr;
  other.size_ = 0;
}

SharedMemory& SharedMemory::operator=(SharedMemory&& other) noexcept {
  if (this != &other) {
    release();
    data_ = other.data_;
    size_ = other.size_;
    other.data_ = nullptr;
    other.size_ = 0;
  }
  return *this;
}

void SharedMemory::release() noexcept {
  if (data_ != nullptr) (void)::munmap(data_, size_);
  data_ = nullptr;
  size_ = 0;
}

Result<SharedMemory> SharedMemory::create_exclusive(const char* name, std::size_t size) noexcept {
  if (!valid_shared_memory_name(name)) return make_error(Errc::invalid_argument, "shared-memory name");
  if (size == 0) return make_error(Errc::invalid_argument, "shared-memory size 0");
  const int fd = ::shm_open(name, O_CREAT | O_EXCL | O_RDWR | O_CLOEXEC, S_IRUSR | S_IWUSR);
  if (fd < 0) {
    if (errno == EEXIST) return make_error(Errc::busy, "shared-memory name exists");
    return os_error("shm_open (create)", errno);
  }
  // 0600 whatever the umask: only this user maps it.
  if (::fchmod(fd, S_IRUSR | S_IWUSR) != 0 || ::ftruncate(fd, static_cast<off_t>(size)) != 0) {
    const int err = errno;
    (void)::close(fd);
    (void)::shm_unlink(name);
    return os_error("ftruncate shared memory", err);
  }
  const Result<void*> region = map_and_close(fd, size);
  if (!region.ok()) {
    (void)::shm_unlink(name);
    return region.error();
  }
  SharedMemory memory;
  memory.data_ = region.value();
  memory.size_ = size;
  return memory;
}

Result<SharedMemory> SharedMemory::open_existing(const char* name) noexcept {
  if (!valid_shared_memory_name(name)) return make_error(Errc::invalid_argument, "shared-memory name");
  const int fd = ::shm_open(name, O_RDWR | O_CLOEXEC, 0);
  if (fd < 0) {
    if (errno == ENOENT) return make_error(Errc::not_found, "no shared-memory segment of that name");
    if (errno == EACCES) return make_error(Errc::permission_denied, kForeignSegment, owner_without_opening(name));
    return os_error("shm_open (attach)", errno);
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const int err = errno;
    (void)::close(fd);
    return os_error("fstat shared memory", err);
  }
  if (st.st_uid != ::geteuid()) {  // never trusted, never mapped, never unlinked (not even by root)
    (void)::close(fd);
    return make_error(Errc::permission_denied, kForeignSegment, static_cast<std::uint32_t>(st.st_uid));
  }
  if (st.st_size <= 0) {
    (void)::close(fd);
    return make_error(Errc::truncated, "shared-memory segment is empty");
  }
  const auto bytes = static_cast<std::size_t>(st.st_size);
  const Result<void*> region = map_and_close(fd, bytes);
  if (!region.ok()) return region.error();
  SharedMemory memory;
  memory.data_ = region.value();
  memory.size_ = bytes;
  return memory;
}

Status SharedMemory::unlink(const char* name) noexcept {
  if (!valid_shared_memory_name(name)) return make_error(Errc::invalid_argument, "shared-memory name");
  if (::shm_unlink(name) == 0) return Status::success();
  if (errno == ENOENT) return make_error(Errc::not_found, "no shared-memory segment of that name");
  return os_error("shm_unlink", errno);
}

Status SharedMemory::lock() noexcept {
  if (data_ == nullptr) return make_error(Errc::invalid_argument, "mlock: nothing mapped");
  if (::mlock(data_, size_) != 0) return os_error("mlock shared memory", errno);
  return Status::success();
}

}  // namespace rescue::hal
