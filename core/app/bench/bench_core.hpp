// `rescue-motion bench core`: what the foundation costs and proves on this machine. Applies the
// real-time set-up (and prints its report), calibrates the TSC, declares init complete, then
// measures the timer itself, clock_gettime, the SPSC queue between two threads (round trip and
// throughput), the seqlock and the histogram, and finally reports the heap allocations and page
// faults that happened after init (both should be 0).
#pragma once

#include "core/app/config/command_line.hpp"

namespace rescue::app {

int bench_core(const ParsedArgs& args) noexcept;

}  // namespace rescue::app
