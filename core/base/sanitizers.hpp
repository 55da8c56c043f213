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

namespace rescue {

// ASan and TSan both own malloc and reserve terabytes of shadow address space (never mlockall it).
inline constexpr bool kSanitizerInterceptsMalloc = RESCUE_SANITIZER_INTERCEPTS_MALLOC != 0;

}  // namespace rescue
