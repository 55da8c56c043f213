// `rescue-motion bench latency`: how much worse than the OS floor the firmware's own periodic loop
// wakes. Runs, one after the other on the same machine, period, SCHED_FIFO priority and CPU:
//   1. the EtherCAT handler's loop shape (hal::MonotonicClock::sleep_until, i.e. clock_nanosleep
//      TIMER_ABSTIME on CLOCK_MONOTONIC, then a clock read), recording release-to-wake latency;
//   2. Debian rt-tests' cyclictest (-m -q -t1 -p PRIO -a CPU -i PERIOD -l N -h ...; clock_nanosleep
//      TIMER_ABSTIME is its default since rt-tests 2.x);
// and prints both as `key: value unit` lines and their ratios (ours / cyclictest) of median, p99
// and max. The machine's conditions come first: kernel (PREEMPT_RT or not), privileges, CPUs,
// and the real-time settings the OS refused.
#pragma once

#include "core/app/config/command_line.hpp"

namespace rescue::app {

int bench_latency(const ParsedArgs& args) noexcept;

}  // namespace rescue::app
