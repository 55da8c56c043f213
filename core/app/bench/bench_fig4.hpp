// `rescue-motion bench fig4`: the paper's section IV-B experiment (Fig. 4). Two real-time tasks run
// each on its own thread at 1 kHz on the wall clock, SCHED_FIFO at their Table I priorities:
//   ethercat  the EtherCAT handler's period (EthercatHandler::cycle) on the in-process simulated
//             robot (as `run --nic sim`: the simulator runs inside the handler's send, on the wall clock)
//   rc        the RC task's period (kin::RcPeriod: the rescue motion, one task-priority IK step,
//             the teleoperation task) from the ready posture, the motion repeating
// for --periods N periods twice: case `without_affinity` (each thread may run on every CPU), then
// case `with_affinity` (each thread pinned to its Table I CPU, core/app/config/task_table.cpp; a
// CPU the machine lacks falls back to its last CPU: table_cpu_on_this_machine). Under a background
// load that is part of the command (--load, default stress,udp):
//   stress    Debian's stress-ng, one CPU and one memory (vm) stressor, confined with --taskset to
//             the "basic software" CPU set (Table I CPU 0), for the whole experiment
//   udp       a sender thread (on the basic software CPU) sending 2000 datagrams/s to a real
//             SocketHandler (core/app/tasks/socket_handler.hpp) on a loopback port: authenticated
//             status queries (answered) and garbage (rejected and counted); the socket handler's
//             thread follows the case's affinity (Table I CPU 1 when pinned)
// Each period's execution time (TSC) and wake-up latency go into a PeriodRecorder per task and case
// and into a fixed per-period series; at the end it writes DIR/fig4.csv (case,task,period,
// execution_ns,latency_ns) and DIR/fig4-summary.csv (PeriodRecorder::write_csv), prints the
// summary as `key: value unit` lines, and draws DIR/fig4.png with toolchain/plot_fig4.py
// (matplotlib; --no-plot skips it). Before the figures it prints what the machine gave: kernel
// (stock or PREEMPT_RT), privileges, CPUs, the mapping of the four Table I CPUs onto this machine,
// and each real-time setting applied or refused.
#pragma once

#include "core/app/config/command_line.hpp"

namespace rescue::app {

int bench_fig4(const ParsedArgs& args) noexcept;

}  // namespace rescue::app
