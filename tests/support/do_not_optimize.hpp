// Test helper: makes the compiler believe a pointer escapes, so an allocation made only to be
// observed (heap guard tests) is not removed as dead code (new/delete pairs may be elided).
#pragma once

namespace rescue::test {

inline void do_not_optimize(const void* pointer) { asm volatile("" : : "g"(pointer) : "memory"); }

}  // namespace rescue::test
