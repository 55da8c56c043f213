// StartUpSlot<T>: the storage of one large object taken from the heap at start-up (`reserve()`,
// before init completes: heap_guard.hpp), the object built in it later (`emplace()`, no allocation,
// so also after init), never freed (it lives as long as the process).
//
// Why not a static object: static storage is part of every command's image, and `run` locks its
// whole image in every task process (mlockall, core/app/runtime/task_loops.cpp). The benchmarks'
// simulated robots, buses and series (about 14 MiB) cost `run` that much locked RAM per process and
// the page faults to populate it at start-up, although `run` never uses them. A command that needs
// such an object reserves it when it starts; the others pay nothing.
#pragma once

#include <cassert>
#include <cstddef>
#include <new>
#include <utility>

namespace rescue {

template <typename T>
class StartUpSlot {
 public:
  StartUpSlot() = default;
  StartUpSlot(const StartUpSlot&) = delete;
  StartUpSlot& operator=(const StartUpSlot&) = delete;
  StartUpSlot(StartUpSlot&&) = delete;
  StartUpSlot& operator=(StartUpSlot&&) = delete;
  ~StartUpSlot() = default;  // never frees: the object may be in use until the process exits

  // Takes the memory (once; later calls do nothing). False: the heap refused it.
  [[nodiscard]] bool reserve() noexcept {
    if (memory_ == nullptr) memory_ = ::operator new(sizeof(T), std::align_val_t{alignof(T)}, std::nothrow);
    return memory_ != nullptr;
  }
  bool reserved() const noexcept { return memory_ != nullptr; }

  // Builds the object in the reserved memory at the first call (later calls return it unchanged).
  // Precondition: reserved() (an internal invariant of the command that owns the slot).
  template <typename... Args>
  T& emplace(Args&&... args) noexcept {
    assert(reserved());
    if (!built()) object_ = ::new (memory_) T(std::forward<Args>(args)...);
    return *object_;
  }
  bool built() const noexcept { return object_ != nullptr; }

 private:
  void* memory_{nullptr};
  T* object_{nullptr};
};

}  // namespace rescue
