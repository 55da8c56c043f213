#!/usr/bin/env bash
# Instructions per period of each real-time task in each of bench wcet's scenarios, counted by
# valgrind's callgrind: the mean, and each period's own count (the heaviest, at which period, and the
# median) (docs/timing.md "Worst-path scenarios"): the count
# does not depend on the machine's load, so which scenario drives the heaviest path is known by
# construction. This machine's VM exposes no hardware counter (no perf `cpu` event source), so the
# per-period count comes from callgrind: collection on only inside the measured period functions
# (wcet_*_period), each of which dumps the counters at its end (a client request,
# core/app/bench/wcet_period_mark.hpp; the dump's trigger names the task); the handler's leaves out
# the simulated NIC (its send and receive toggle collection off: they stand in for the wire).
# Each task's first period is left out: the first dump also holds the bring-up's NIC toggles.
#
# Usage: toolchain/wcet/instructions.sh [BINARY] [PERIODS] [SCENARIO...]
#   BINARY    default build/release/rescue-motion
#   PERIODS   measured periods per scenario, default 2000 (bench wcet's least)
#   SCENARIO  default: typical worst (worst-ring: the ring configuration's)
# Prints per scenario and task `SCENARIO.TASK_instructions_per_period: N instructions` (the mean),
# `SCENARIO.TASK_instructions_max_period: N instructions (period K)` and
# `SCENARIO.TASK_instructions_median_period: N instructions`; with worst and another scenario, per
# task `worst_heaviest.TASK: yes|no (...)` (worst's heaviest period against the others') and
# `heaviest.TASK: SCENARIO N` (the scenario with the largest heaviest period); exit 1
# when valgrind is missing or a run fails (a `no` is reported, not an exit status).
set -euo pipefail
cd "$(dirname "$0")/../.."
binary=${1:-build/release/rescue-motion}
periods=${2:-2000}
shift $(( $# > 2 ? 2 : $# ))
scenarios=("$@")
[ "${#scenarios[@]}" -gt 0 ] || scenarios=(typical worst)
command -v valgrind >/dev/null || { echo "instructions: valgrind not installed (toolchain/setup.sh)"; exit 1; }
[ -x "$binary" ] || { echo "instructions: $binary missing (cmake --build build/release --target rescue-motion)"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
tasks=(ethercat_handler joint_manager message_parser rc_tasks socket_handler)
functions=(wcet_handler_period wcet_joint_manager_period wcet_message_parser_period wcet_rc_period wcet_socket_handler_period)

echo "instructions_periods: $periods periods per scenario (mean; each period's own count: max, median)"
echo "instructions_valgrind: $(valgrind --version)"
for scenario in "${scenarios[@]}"; do
  toggles=()
  for f in "${functions[@]}"; do toggles+=("--toggle-collect=rescue::app::$f*"); done
  # bench wcet's statistics run afterwards in a child (python3), which valgrind does not follow.
  # --scheduling normal: some 50 times slower under callgrind, a SCHED_FIFO run would hold a whole CPU
  # for minutes and starve the machine's other real-time work; the count does not depend on it.
  valgrind --tool=callgrind --collect-atstart=no --dump-instr=no --dump-line=no "${toggles[@]}" \
    '--toggle-collect=rescue::drivers::SimulatedNic::send(*' '--toggle-collect=rescue::drivers::SimulatedNic::receive(*' \
    --callgrind-out-file="$work/$scenario.out" \
    "$binary" bench wcet --scenario "$scenario" --periods "$periods" --scheduling normal --no-plot --out "$work/$scenario-out" \
    > "$work/$scenario.log" 2> "$work/$scenario.err" || {
      status=$?
      # 2 (refused) and 3 (over budget) are verdicts of the statistics, not failed runs.
      [ "$status" -eq 2 ] || [ "$status" -eq 3 ] || { echo "instructions: $scenario run failed:" >&2; tail -5 "$work/$scenario.err" >&2; exit 1; }
    }
  # Each dump: its trigger (`Client Request: TASK`) and its total, in dump order; per task the
  # largest (and at which of its periods) and the median.
  ls "$work" | grep -E "^$scenario\.out\.[0-9]+$" | sort -t. -k3 -n | sed "s|^|$work/|" |
    { /usr/bin/python3 toolchain/wcet/callgrind_periods.py "$scenario" "${tasks[@]}" || true; } | tee -a "$work/maxima.txt"
  find "$work" -maxdepth 1 -name "$scenario.out.*" -delete  # 5 dumps a period: too many for rm's arguments
done
# With worst and another scenario: per task, whether worst's heaviest period is at least every other
# scenario's (its heaviest path driven by construction, not luck); with several scenarios, per task
# the one whose heaviest period is the largest (`heaviest.TASK: SCENARIO N`: worst-ring's for the
# handler when the ring's path is heavier than the tree's).
if [ "${#scenarios[@]}" -gt 1 ]; then
  /usr/bin/python3 -c '
import re, sys
maxima = {}
for line in open(sys.argv[1]):
    m = re.match(r"([\w-]+)\.(\w+)_instructions_max_period: (\d+) ", line)
    if m:
        maxima.setdefault(m.group(2), {})[m.group(1)] = int(m.group(3))
for task, by in maxima.items():
    top = max(by, key=by.get)
    print(f"heaviest.{task}: {top} {by[top]}")
    if "worst" not in by:
        continue
    others = {s: n for s, n in by.items() if s != "worst"}
    worst = by["worst"]
    above = {s: n for s, n in others.items() if n > worst}
    if above:
        print(f"worst_heaviest.{task}: no (worst {worst}; above it: " + ", ".join(f"{s} {n}" for s, n in above.items()) + ")")
    else:
        print(f"worst_heaviest.{task}: yes (worst {worst} >= " + ", ".join(f"{s} {n}" for s, n in others.items()) + ")")
' "$work/maxima.txt"
fi
