// The whole of one ctl command within --timeout (docs/security.md): each exchange has its own
// deadline, and this watchdog (SIGALRM) covers every other phase (the key and configuration files,
// the state directory), so nothing found at a path and no system call can make ctl wait past it.
// It ends the process with "stopped: no result within --timeout" and exit status 3 (unreachable).
#pragma once

namespace rescue::app {

constexpr double kKeygenDefaultTimeoutSeconds = 10.0;  // keygen's durable write alone can take seconds

// Arms (or re-arms) the watchdog: `seconds` plus half a second, so the exchange's own deadline comes first.
void arm_ctl_deadline(double seconds) noexcept;
void disarm_ctl_deadline() noexcept;

}  // namespace rescue::app
