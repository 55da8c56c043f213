// `rescue-motion bench periods`: the firmware's real-time tasks as `run` wires them (the EtherCAT
// handler and the joint manager over one TaskLinks), stepped by one thread on the simulated robot in
// virtual time: deterministic, so a count of instructions per period is the same on every machine.
// After bring-up to OP and "initialize robot" (every joint Enabled), it runs --cycles periods, each
// the handler's cycle (measured_handler_period) then the joint manager's step
// (measured_joint_manager_step), then the RC task's period (measured_rc_period: kin::RcPeriod doing
// the rescue motion, not yet wired to the other two), and prints their execution time per period (TSC).
// toolchain/instructions.sh runs it under callgrind, collecting only inside those two functions
// (and not inside the simulated NIC, which stands in for the wire), for instructions per period.
#pragma once

#include "core/app/config/command_line.hpp"

namespace rescue::app {

int bench_periods(const ParsedArgs& args) noexcept;

}  // namespace rescue::app
