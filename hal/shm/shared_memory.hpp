// POSIX shared memory (shm_open + ftruncate + mmap), one RAII mapping: the OS side of the tasks'
// shared-memory segment (core/app/shm/ gives it its layout and header, docs/shared-memory.md).
//
//   create_exclusive  shm_open(O_CREAT | O_EXCL | O_RDWR, 0600), ftruncate to the size, mmap
//                     MAP_SHARED: the pages read zero. Fails with busy when the name exists.
//   open_existing     shm_open(O_RDWR), its owner and size from fstat, mmap MAP_SHARED; a segment
//                     another user owns is refused (kForeignSegment), never mapped.
//   lock              mlock of the mapping (no page fault once the tasks run).
//   unlink            shm_unlink: the name goes, mappings stay valid until unmapped.
//
// The mapping is unmapped when the object goes away; the name is never unlinked implicitly (the
// owner decides, core/app/shm/shared_segment.hpp). Names follow shm_open(3): "/" then up to
// kMaxNameLength - 1 characters, none of them '/'.
#pragma once

#include <cstddef>

#include "core/base/result.hpp"

namespace rescue::hal {

// The error's `what` for a segment another user owns (detail0: its uid, 0xFFFFFFFF when unknown).
constexpr const char* kForeignSegment = "shared-memory segment owned by another user";

class SharedMemory {
 public:
  static constexpr std::size_t kMaxNameLength = 200;

  SharedMemory() = default;
  ~SharedMemory();
  SharedMemory(const SharedMemory&) = delete;
  SharedMemory& operator=(const SharedMemory&) = delete;
  SharedMemory(SharedMemory&& other) noexcept;
  SharedMemory& operator=(SharedMemory&& other) noexcept;

  // Errors: invalid_argument "shared-memory name" (not "/x", too long or with a second '/'),
  // busy "shared-memory name exists", permission_denied / io_error with errno in detail0.
  static Result<SharedMemory> create_exclusive(const char* name, std::size_t size) noexcept;
  // Errors: not_found "no shared-memory segment of that name", permission_denied kForeignSegment
  // (owned by another user: detail0 its uid), permission_denied / io_error (errno).
  static Result<SharedMemory> open_existing(const char* name) noexcept;
  // Errors: not_found when the name does not exist, io_error (errno in detail0).
  static Status unlink(const char* name) noexcept;

  // Locks the mapping in RAM. Errors: permission_denied / io_error "mlock" (errno in detail0).
  Status lock() noexcept;

  void* data() const noexcept { return data_; }
  std::size_t size() const noexcept { return size_; }
  bool mapped() const noexcept { return data_ != nullptr; }

 private:
  void release() noexcept;

  void* data_{nullptr};
  std::size_t size_{0};
};

// Whether `name` is a valid shm_open name by the rule above.
bool valid_shared_memory_name(const char* name) noexcept;

}  // namespace rescue::hal
