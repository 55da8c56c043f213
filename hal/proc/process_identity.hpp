// Who a process is, beyond its pid: pids are reused, so "the process that created this" is a pid
// and its start time (field 22 of /proc/PID/stat, clock ticks since boot). A process is the same one
// only when both match. Used to tell a live segment creator from a stale segment (core/app/shm/).
#pragma once

#include <cstdint>
#include <sys/types.h>

#include "core/base/result.hpp"

namespace rescue::hal {

struct ProcessIdentity {
  std::int32_t pid{0};
  std::uint64_t start_time{0};  // clock ticks since boot (/proc/PID/stat field 22)
};

// Start time of `pid`. Errors: not_found when no such process, malformed when /proc's line does
// not parse, io_error (errno in detail0).
Result<std::uint64_t> process_start_time(pid_t pid) noexcept;

// The calling process.
Result<ProcessIdentity> own_process_identity() noexcept;

// The calling thread's kernel id (gettid: what `chrt -p`, `ps -L` and /proc/PID/task/ name).
std::int32_t own_thread_id() noexcept;

// True when `who.pid` runs and started at `who.start_time` (a reused pid is not alive). A zombie
// (dead, not yet reaped) counts as dead.
bool process_alive(const ProcessIdentity& who) noexcept;

}  // namespace rescue::hal
