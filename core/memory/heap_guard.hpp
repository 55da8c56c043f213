// Heap guard: proves "no heap after init". The library rescue_heap_guard replaces operator new /
// new[] / delete (every form, aligned and nothrow included) and, in builds without ASan/TSan, the C
// allocator (malloc, calloc, realloc, aligned_alloc, posix_memalign, memalign, valloc, pvalloc,
// free). Until declare_init_complete() it only forwards to glibc. Afterwards every allocation is
// counted by kind and size; in strict mode the first one aborts the process with a line such as
//     heap guard: operator new(48) after init complete
// so the offending call is the top of the core dump / debugger stack.
//
// Linking rescue_heap_guard is a conscious choice: it is an object library (its replacements must
// be linked, not picked from an archive on demand) that only the program and the tests that arm
// it link. Code that merely calls the functions below without linking it does not link.
//
// Coverage by build (heap_guard_covers_malloc() says which at run time):
//   debug/release/wcet/motion-pc/aarch64: operator new family + C allocator (glibc, via __libc_*).
//   asan/tsan (RESCUE_SANITIZE): operator new family only. The sanitizer runtime owns malloc; a
//     second definition would hide allocations from it. operator new is still ours and forwards to
//     the sanitizer's malloc, so leaks and overflows are still found.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace rescue {

enum class HeapEvent : std::uint8_t {
  operator_new,
  operator_new_array,
  operator_new_aligned,
  operator_new_array_aligned,
  malloc,
  calloc,
  realloc,
  aligned_alloc,
  posix_memalign,
  memalign,
  valloc,
  pvalloc,
};
inline constexpr std::size_t kHeapEventKinds = 12;

// How the guard reacts to an allocation after init complete.
enum class HeapGuardMode : std::uint8_t {
  count,   // count it (read the counters and report them)
  strict,  // print which allocation it was and abort()
};

struct HeapGuardCounters {
  std::uint64_t allocations{0};  // all kinds, after init complete, outside HeapAllowedScope
  std::uint64_t bytes{0};        // requested bytes of those allocations
  std::uint64_t frees{0};        // free/delete of non-null pointers after init complete
  std::uint64_t allowed{0};      // allocations inside a HeapAllowedScope (never abort)
  std::array<std::uint64_t, kHeapEventKinds> by_kind{};  // index: static_cast<std::size_t>(HeapEvent)
};

// From now on allocations are counted (and abort, in strict mode). Call once the program has
// allocated everything it will ever need.
void declare_init_complete(HeapGuardMode mode = HeapGuardMode::count) noexcept;
void set_heap_guard_mode(HeapGuardMode mode) noexcept;
bool heap_init_complete() noexcept;
HeapGuardCounters heap_guard_counters() noexcept;
// True when malloc and friends are covered (false in ASan/TSan builds: operator new only).
bool heap_guard_covers_malloc() noexcept;
// "operator new", "malloc", ...
const char* to_string(HeapEvent event) noexcept;

// Tests and tools only: back to the init phase (nothing counted), counters zeroed, mode count.
void reopen_init_for_testing() noexcept;

// Allocations made by this thread while a scope is alive are counted as `allowed` and never abort:
// for a non-real-time thread with a documented reason (e.g. the operator console's line editor).
class HeapAllowedScope {
 public:
  HeapAllowedScope() noexcept;
  ~HeapAllowedScope();
  HeapAllowedScope(const HeapAllowedScope&) = delete;
  HeapAllowedScope& operator=(const HeapAllowedScope&) = delete;
  HeapAllowedScope(HeapAllowedScope&&) = delete;
  HeapAllowedScope& operator=(HeapAllowedScope&&) = delete;
};

}  // namespace rescue
