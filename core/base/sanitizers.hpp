// Which sanitizer this translation unit is built with. Code that replaces what a sanitizer
// intercepts (the heap guard's malloc) or that a sanitizer's shadow memory makes unsafe (mlockall)
// asks here rather than each file repeating the compiler-specific tests.
#pragma once

// GCC defines __SANITIZE_*__; clang answers __has_feature.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define RESCUE_SANITIZER_INTERCEPTS_MALLOC 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define RESCUE_SANITIZER_INTERCEPTS_MALLOC 1
#endif
#endif
#ifndef RESCUE_SANITIZER_INTERCEPTS_MALLOC
#define RESCUE_SANITIZER_INTERCEPTS_MALLOC 0
#endif
#if defined(__SANITIZE_THREAD__)
#define RESCUE_THREAD_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define RESCUE_THREAD_SANITIZER 1
#endif
#endif
#ifndef RESCUE_THREAD_SANITIZER
#define RESCUE_THREAD_SANITIZER 0
#endif
#if defined(__SANITIZE_ADDRESS__)
#define RESCUE_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define RESCUE_ADDRESS_SANITIZER 1
#endif
#endif
#ifndef RESCUE_ADDRESS_SANITIZER
#define RESCUE_ADDRESS_SANITIZER 0
#endif

namespace rescue {

// ASan and TSan both own malloc and reserve terabytes of shadow address space (never mlockall it).
inline constexpr bool kSanitizerInterceptsMalloc = RESCUE_SANITIZER_INTERCEPTS_MALLOC != 0;
// TSan's runtime guards its bookkeeping (of every atomic access, among others) with spin locks that
// wait by sched_yield, never by sleeping (StaticSpinMutex). A SCHED_FIFO thread spinning on one
// whose holder is a lower-priority thread on the same CPU never lets the holder run: the whole
// process hangs (a CI run: the firmware's tasks, all on CPU 1 of 2, still after 600 s).
inline constexpr bool kThreadSanitizer = RESCUE_THREAD_SANITIZER != 0;
inline constexpr bool kAddressSanitizer = RESCUE_ADDRESS_SANITIZER != 0;
// ASan's runtime is built on the same sanitizer_common spin locks (StaticSpinMutex: spin, then
// sched_yield, never sleep), taken in its allocator and at thread start and end: the same hang is
// possible, so ASan builds refuse SCHED_FIFO too (docs/build.md).
inline constexpr bool kSanitizerSpinsBySchedYield = kThreadSanitizer || kAddressSanitizer;

}  // namespace rescue
