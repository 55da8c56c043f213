#include "hal/files/mapped_file.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <utility>

namespace rescue::hal {

MappedFile::~MappedFile() { release(); }

MappedFile::MappedFile(MappedFile&& other) noexcept
    : data_(std::exchange(other.data_, nullptr)), size_(std::exchange(other.size_, 0)) {}

MappedFile& MappedFile::operator=(MappedFile&& other) noexcept {
  if (this != &other) {
    release();
    data_ = std::exchange(other.data_, nullptr);
    size_ = std::exchange(other.size_, 0);
  }
  return *this;
}

Result<MappedFile> MappedFile::open(const char* path) noexcept {
  const int fd = ::open(path, O_RDONLY | O_CLOEXEC);  // NOLINT(cppcoreguidelines-pro-type-vararg)
  if (fd < 0) return make_error(Errc::io_error, "open file", static_cast<std::uint32_t>(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const int error = errno;
    (void)::close(fd);
    return make_error(Errc::io_error, "stat file", static_cast<std::uint32_t>(error));
  }
  if (!S_ISREG(st.st_mode)) {
    (void)::close(fd);
    return make_error(Errc::invalid_argument, "not a regular file");
  }
  MappedFile file;
  if (st.st_size > 0) {
    const auto size = static_cast<std::size_t>(st.st_size);
    void* p = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
    if (p == MAP_FAILED) {  // NOLINT(cppcoreguidelines-pro-type-cstyle-cast): the libc macro
      const int error = errno;
      (void)::close(fd);
      return make_error(Errc::io_error, "map file", static_cast<std::uint32_t>(error));
    }
    file.data_ = static_cast<const std::uint8_t*>(p);
    file.size_ = size;
  }
  (void)::close(fd);  // the mapping stays valid without the descriptor
  return file;
}

void MappedFile::release() noexcept {
  if (data_ != nullptr) {
    (void)::munmap(const_cast<std::uint8_t*>(data_), size_);  // NOLINT(cppcoreguidelines-pro-type-const-cast)
    data_ = nullptr;
    size_ = 0;
  }
}

}  // namespace rescue::hal
