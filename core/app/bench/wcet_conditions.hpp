// The conditions bench wcet's figures are read with (docs/timing.md "pWCET of the tasks"): kernel,
// PREEMPT_RT or not, CPUs online, the machine's load average at the start and at the end of the
// measuring, and whether the measuring thread got its real-time set-up. Printed as one
// `conditions:` line beside the figures (a reader of the figures alone sees them), and as a `#`
// line in each samples file.
#pragma once

#include <cstddef>

namespace rescue::app {

// /proc/loadavg's first three fields into `out` ("n/a" when unreadable).
void read_load_average(char* out, std::size_t size) noexcept;

// "kernel R, PREEMPT_RT yes|no, N CPUs online, load average A at start, B at end, real-time set-up S"
// into `out`; `load_at_start` as read_load_average gave it, `real_time` false for --scheduling normal,
// `rt_applied` from the rt: lines.
void describe_wcet_conditions(char* out, std::size_t size, const char* load_at_start, bool real_time, bool rt_applied) noexcept;

}  // namespace rescue::app
