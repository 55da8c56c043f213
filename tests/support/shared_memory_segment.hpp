// Test helper: a named POSIX shared-memory segment (shm_open + ftruncate + mmap) that a forked
// child can open again by name and map at a different address, the way the firmware's processes
// meet. The creator unlinks the name when it goes out of scope.
#pragma once

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdio>

namespace rescue::test {

class SharedMemorySegment {
 public:
  // Creates (or truncates) /rescue-test-<tag>-<pid> of `size` bytes.
  SharedMemorySegment(const char* tag, std::size_t size) : size_(size) {
    std::snprintf(name_, sizeof name_, "/rescue-test-%s-%d", tag, static_cast<int>(getpid()));
    shm_unlink(name_);  // a leftover of a crashed run
    const int fd = shm_open(name_, O_CREAT | O_EXCL | O_RDWR, 0600);
    if (fd < 0) return;
    if (ftruncate(fd, static_cast<off_t>(size)) == 0) address_ = map_fd(fd, size);
    close(fd);
  }
  ~SharedMemorySegment() {
    if (address_ != nullptr) munmap(address_, size_);
    shm_unlink(name_);
  }
  SharedMemorySegment(const SharedMemorySegment&) = delete;
  SharedMemorySegment& operator=(const SharedMemorySegment&) = delete;

  bool ok() const { return address_ != nullptr; }
  void* address() const { return address_; }
  const char* name() const { return name_; }

  // In the child: a second, independent mapping of the same segment (a new address).
  void* map_again() const {
    const int fd = shm_open(name_, O_RDWR, 0600);
    if (fd < 0) return nullptr;
    void* address = map_fd(fd, size_);
    close(fd);
    return address;
  }

 private:
  static void* map_fd(int fd, std::size_t size) {
    void* address = mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    return address == MAP_FAILED ? nullptr : address;
  }

  char name_[64]{};
  std::size_t size_;
  void* address_{nullptr};
};

}  // namespace rescue::test
