// `rescue-motion bench wcet`: the probabilistic WCET of each real-time task on its heaviest path
// (issue 38; docs/timing.md "pWCET of the tasks"). The tasks as `run` wires them (EtherCAT handler,
// joint manager, message parser over one TaskLinks; the RC tasks' period kin::RcPeriod, as bench
// periods runs it) stepped by one thread on the simulated robot in virtual time, while a scenario
// (core/app/bench/wcet_scenarios.hpp) drives the worst paths. Each period's execution time of each
// task (TSC) goes into an array reserved at start-up (no heap after init); then one file per task
// in --out and toolchain/wcet/pwcet.py on them (Debian's /usr/bin/python3 with scipy): i.i.d. tests,
// the GEV fit and its goodness, pWCET at 1e-9 and 1e-12 with their interval, or a refusal; the
// exceedance plot; the budget against Table I (core/app/bench/wcet_budget.hpp).
// Exit status: 0 every task has a pWCET within its budget; 2 a task's samples were refused (no
// pWCET); 3 a task is over its budget; 1 any other failure.
#pragma once

#include "core/app/config/command_line.hpp"

namespace rescue::app {

int bench_wcet(const ParsedArgs& args) noexcept;

}  // namespace rescue::app
