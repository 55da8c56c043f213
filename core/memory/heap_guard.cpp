// Heap guard: replacement operator new/delete and (outside sanitizer builds) the C allocator, each
// noting the allocation and then forwarding to glibc's own allocator. See core/memory/heap_guard.hpp.
//
// Everything here may run before main(), inside other threads and inside glibc itself, so it uses
// only constant-initialised atomics, one initial-exec thread_local int, write(2) and abort(): no
// stdio, no locks, nothing that could allocate or recurse into the allocator.
#include "core/memory/heap_guard.hpp"

#include <malloc.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <new>

#include "core/base/sanitizers.hpp"

// glibc's allocator under its internal names: the replacements below forward here, so glibc's
// allocator still does the work and nothing is counted twice.
extern "C" {
void* __libc_malloc(std::size_t size) noexcept;
void* __libc_calloc(std::size_t count, std::size_t size) noexcept;
void* __libc_realloc(void* ptr, std::size_t size) noexcept;
void* __libc_memalign(std::size_t alignment, std::size_t size) noexcept;
void* __libc_valloc(std::size_t size) noexcept;
void* __libc_pvalloc(std::size_t size) noexcept;
void __libc_free(void* ptr) noexcept;
}

namespace rescue {
namespace {

std::atomic<bool> g_init_complete{false};
std::atomic<HeapGuardMode> g_mode{HeapGuardMode::count};
std::array<std::atomic<std::uint64_t>, kHeapEventKinds> g_by_kind{};
std::atomic<std::uint64_t> g_bytes{0};
std::atomic<std::uint64_t> g_frees{0};
std::atomic<std::uint64_t> g_allowed{0};
// initial-exec: reading it never calls __tls_get_addr, which may itself allocate.
thread_local int t_allowed_depth __attribute__((tls_model("initial-exec"))) = 0;

static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<std::uint64_t>::is_always_lock_free,
              "the guard runs inside malloc: its atomics must not take locks");

// A fixed buffer for the abort message: the allocator cannot be used to report itself.
class Message {
 public:
  void append(const char* text) noexcept {
    while (*text != '\0' && length_ < text_.size()) text_[length_++] = *text++;
  }
  void append(std::uint64_t value) noexcept {
    std::array<char, 24> digits{};
    std::size_t count = 0;
    do {
      digits[count++] = static_cast<char>('0' + value % 10);
      value /= 10;
    } while (value != 0);
    while (count > 0 && length_ < text_.size()) text_[length_++] = digits[--count];
  }
  void write_to_stderr() const noexcept {
    const ssize_t written = ::write(STDERR_FILENO, text_.data(), length_);
    (void)written;  // nothing better to do when stderr is gone: we are about to abort
  }

 private:
  std::array<char, 200> text_{};
  std::size_t length_{0};
};

[[noreturn]] void abort_with(const char* what, HeapEvent event, std::size_t bytes, std::size_t alignment) noexcept {
  Message message;
  message.append("heap guard: ");
  message.append(to_string(event));
  message.append("(");
  message.append(static_cast<std::uint64_t>(bytes));
  if (alignment != 0) {
    message.append(", align ");
    message.append(static_cast<std::uint64_t>(alignment));
  }
  message.append(") ");
  message.append(what);
  message.append("\n");
  message.write_to_stderr();
  std::abort();
}

void note_allocation(HeapEvent event, std::size_t bytes, std::size_t alignment = 0) noexcept {
  if (!g_init_complete.load(std::memory_order_relaxed)) return;
  if (t_allowed_depth > 0) {
    g_allowed.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  g_by_kind[static_cast<std::size_t>(event)].fetch_add(1, std::memory_order_relaxed);
  g_bytes.fetch_add(bytes, std::memory_order_relaxed);
  if (g_mode.load(std::memory_order_relaxed) == HeapGuardMode::strict) {
    abort_with("after init complete", event, bytes, alignment);
  }
}

void note_free(const void* ptr) noexcept {
  if (ptr != nullptr && g_init_complete.load(std::memory_order_relaxed)) {
    g_frees.fetch_add(1, std::memory_order_relaxed);
  }
}

// The allocator operator new forwards to: glibc directly, or the sanitizer's malloc.
void* raw_malloc(std::size_t bytes) noexcept {
#if RESCUE_SANITIZER_INTERCEPTS_MALLOC
  return std::malloc(bytes);  // NOLINT(cppcoreguidelines-no-malloc,hicpp-no-malloc): operator new's backend
#else
  return __libc_malloc(bytes);
#endif
}

void* raw_aligned(std::size_t alignment, std::size_t bytes) noexcept {
#if RESCUE_SANITIZER_INTERCEPTS_MALLOC
  void* ptr = nullptr;
  return posix_memalign(&ptr, alignment < sizeof(void*) ? sizeof(void*) : alignment, bytes) == 0 ? ptr : nullptr;
#else
  return __libc_memalign(alignment, bytes);
#endif
}

void raw_free(void* ptr) noexcept {
#if RESCUE_SANITIZER_INTERCEPTS_MALLOC
  std::free(ptr);  // NOLINT(cppcoreguidelines-no-malloc,hicpp-no-malloc): operator delete's backend
#else
  __libc_free(ptr);
#endif
}

// operator new's contract without exceptions: retry through the new-handler, abort when there is
// none (where a hosted build would throw std::bad_alloc). `nothrow` returns nullptr instead.
void* new_impl(HeapEvent event, std::size_t bytes, std::size_t alignment, bool nothrow) noexcept {
  note_allocation(event, bytes, alignment);
  const std::size_t size = bytes == 0 ? 1 : bytes;  // every new returns a distinct pointer
  for (;;) {
    void* ptr = alignment == 0 ? raw_malloc(size) : raw_aligned(alignment, size);
    if (ptr != nullptr) return ptr;
    const std::new_handler handler = std::get_new_handler();
    if (handler == nullptr) {
      if (nothrow) return nullptr;
      abort_with("failed: out of memory", event, bytes, alignment);
    }
    handler();
  }
}

void delete_impl(void* ptr) noexcept {
  note_free(ptr);
  raw_free(ptr);
}

std::size_t align_of(std::align_val_t alignment) noexcept { return static_cast<std::size_t>(alignment); }

}  // namespace

void declare_init_complete(HeapGuardMode mode) noexcept {
  g_mode.store(mode, std::memory_order_relaxed);
  g_init_complete.store(true, std::memory_order_release);
}

void set_heap_guard_mode(HeapGuardMode mode) noexcept { g_mode.store(mode, std::memory_order_relaxed); }

bool heap_init_complete() noexcept { return g_init_complete.load(std::memory_order_acquire); }

HeapGuardCounters heap_guard_counters() noexcept {
  HeapGuardCounters counters;
  for (std::size_t i = 0; i < kHeapEventKinds; ++i) {
    counters.by_kind[i] = g_by_kind[i].load(std::memory_order_relaxed);
    counters.allocations += counters.by_kind[i];
  }
  counters.bytes = g_bytes.load(std::memory_order_relaxed);
  counters.frees = g_frees.load(std::memory_order_relaxed);
  counters.allowed = g_allowed.load(std::memory_order_relaxed);
  return counters;
}

bool heap_guard_covers_malloc() noexcept { return !kSanitizerInterceptsMalloc; }

const char* to_string(HeapEvent event) noexcept {
  switch (event) {
    case HeapEvent::operator_new: return "operator new";
    case HeapEvent::operator_new_array: return "operator new[]";
    case HeapEvent::operator_new_aligned: return "aligned operator new";
    case HeapEvent::operator_new_array_aligned: return "aligned operator new[]";
    case HeapEvent::malloc: return "malloc";
    case HeapEvent::calloc: return "calloc";
    case HeapEvent::realloc: return "realloc";
    case HeapEvent::aligned_alloc: return "aligned_alloc";
    case HeapEvent::posix_memalign: return "posix_memalign";
    case HeapEvent::memalign: return "memalign";
    case HeapEvent::valloc: return "valloc";
    case HeapEvent::pvalloc: return "pvalloc";
  }
  return "unknown allocation";
}

void reopen_init_for_testing() noexcept {
  g_init_complete.store(false, std::memory_order_release);
  g_mode.store(HeapGuardMode::count, std::memory_order_relaxed);
  for (auto& counter : g_by_kind) counter.store(0, std::memory_order_relaxed);
  g_bytes.store(0, std::memory_order_relaxed);
  g_frees.store(0, std::memory_order_relaxed);
  g_allowed.store(0, std::memory_order_relaxed);
}

HeapAllowedScope::HeapAllowedScope() noexcept { ++t_allowed_depth; }
HeapAllowedScope::~HeapAllowedScope() { --t_allowed_depth; }

}  // namespace rescue

// ---- replacement operator new / delete (every C++17 form) ----------------------------------------
// NOLINTBEGIN(readability-inconsistent-declaration-parameter-name)
using rescue::HeapEvent;

void* operator new(std::size_t bytes) { return rescue::new_impl(HeapEvent::operator_new, bytes, 0, false); }
void* operator new[](std::size_t bytes) { return rescue::new_impl(HeapEvent::operator_new_array, bytes, 0, false); }
void* operator new(std::size_t bytes, const std::nothrow_t& /*tag*/) noexcept {
  return rescue::new_impl(HeapEvent::operator_new, bytes, 0, true);
}
void* operator new[](std::size_t bytes, const std::nothrow_t& /*tag*/) noexcept {
  return rescue::new_impl(HeapEvent::operator_new_array, bytes, 0, true);
}
void* operator new(std::size_t bytes, std::align_val_t alignment) {
  return rescue::new_impl(HeapEvent::operator_new_aligned, bytes, rescue::align_of(alignment), false);
}
void* operator new[](std::size_t bytes, std::align_val_t alignment) {
  return rescue::new_impl(HeapEvent::operator_new_array_aligned, bytes, rescue::align_of(alignment), false);
}
void* operator new(std::size_t bytes, std::align_val_t alignment, const std::nothrow_t& /*tag*/) noexcept {
  return rescue::new_impl(HeapEvent::operator_new_aligned, bytes, rescue::align_of(alignment), true);
}
void* operator new[](std::size_t bytes, std::align_val_t alignment, const std::nothrow_t& /*tag*/) noexcept {
  return rescue::new_impl(HeapEvent::operator_new_array_aligned, bytes, rescue::align_of(alignment), true);
}

void operator delete(void* ptr) noexcept { rescue::delete_impl(ptr); }
void operator delete[](void* ptr) noexcept { rescue::delete_impl(ptr); }
void operator delete(void* ptr, std::size_t /*bytes*/) noexcept { rescue::delete_impl(ptr); }
void operator delete[](void* ptr, std::size_t /*bytes*/) noexcept { rescue::delete_impl(ptr); }
void operator delete(void* ptr, const std::nothrow_t& /*tag*/) noexcept { rescue::delete_impl(ptr); }
void operator delete[](void* ptr, const std::nothrow_t& /*tag*/) noexcept { rescue::delete_impl(ptr); }
void operator delete(void* ptr, std::align_val_t /*alignment*/) noexcept { rescue::delete_impl(ptr); }
void operator delete[](void* ptr, std::align_val_t /*alignment*/) noexcept { rescue::delete_impl(ptr); }
void operator delete(void* ptr, std::size_t /*bytes*/, std::align_val_t /*alignment*/) noexcept {
  rescue::delete_impl(ptr);
}
void operator delete[](void* ptr, std::size_t /*bytes*/, std::align_val_t /*alignment*/) noexcept {
  rescue::delete_impl(ptr);
}
void operator delete(void* ptr, std::align_val_t /*alignment*/, const std::nothrow_t& /*tag*/) noexcept {
  rescue::delete_impl(ptr);
}
void operator delete[](void* ptr, std::align_val_t /*alignment*/, const std::nothrow_t& /*tag*/) noexcept {
  rescue::delete_impl(ptr);
}

// ---- replacement C allocator (glibc supports replacing it: "Replacing malloc" in its manual) ----
#if !RESCUE_SANITIZER_INTERCEPTS_MALLOC
namespace {

bool is_power_of_two(std::size_t value) noexcept { return value != 0 && (value & (value - 1)) == 0; }

std::size_t saturating_product(std::size_t count, std::size_t size) noexcept {
  std::size_t product = 0;
  return __builtin_mul_overflow(count, size, &product) ? SIZE_MAX : product;
}

}  // namespace

extern "C" {

void* malloc(std::size_t bytes) noexcept {
  rescue::note_allocation(HeapEvent::malloc, bytes);
  return __libc_malloc(bytes);
}

void free(void* ptr) noexcept {
  rescue::note_free(ptr);
  __libc_free(ptr);
}

void* calloc(std::size_t count, std::size_t bytes) noexcept {
  rescue::note_allocation(HeapEvent::calloc, saturating_product(count, bytes));
  return __libc_calloc(count, bytes);
}

void* realloc(void* ptr, std::size_t bytes) noexcept {
  if (bytes == 0 && ptr != nullptr) {
    rescue::note_free(ptr);  // glibc: realloc(p, 0) frees p
  } else {
    rescue::note_allocation(HeapEvent::realloc, bytes);
  }
  return __libc_realloc(ptr, bytes);
}

void* aligned_alloc(std::size_t alignment, std::size_t bytes) noexcept {
  rescue::note_allocation(HeapEvent::aligned_alloc, bytes, alignment);
  if (!is_power_of_two(alignment)) {
    errno = EINVAL;
    return nullptr;
  }
  return __libc_memalign(alignment, bytes);
}

int posix_memalign(void** out, std::size_t alignment, std::size_t bytes) noexcept {
  rescue::note_allocation(HeapEvent::posix_memalign, bytes, alignment);
  if (!is_power_of_two(alignment) || alignment % sizeof(void*) != 0) return EINVAL;
  void* ptr = __libc_memalign(alignment, bytes);
  if (ptr == nullptr) return ENOMEM;
  *out = ptr;
  return 0;
}

void* memalign(std::size_t alignment, std::size_t bytes) noexcept {
  rescue::note_allocation(HeapEvent::memalign, bytes, alignment);
  return __libc_memalign(alignment, bytes);
}

void* valloc(std::size_t bytes) noexcept {
  rescue::note_allocation(HeapEvent::valloc, bytes);
  return __libc_valloc(bytes);
}

void* pvalloc(std::size_t bytes) noexcept {
  rescue::note_allocation(HeapEvent::pvalloc, bytes);
  return __libc_pvalloc(bytes);
}

}  // extern "C"
#endif  // !RESCUE_SANITIZER_INTERCEPTS_MALLOC
// NOLINTEND(readability-inconsistent-declaration-parameter-name)
