// The header every `rescue-motion bench NAME` prints before its figures: what was measured and on
// what (CPU, kernel, privileges), so a figure is never read without its conditions.
#pragma once

#include <cstdio>

namespace rescue::app {

// Prints "bench: NAME", "cpu: ...", "kernel: ...", "privileges: ..." lines to `out`.
void print_bench_header(std::FILE* out, const char* name) noexcept;
// Whether the kernel is PREEMPT_RT: uname's version names PREEMPT_RT, or /sys/kernel/realtime reads 1.
bool kernel_is_preempt_rt() noexcept;

}  // namespace rescue::app
