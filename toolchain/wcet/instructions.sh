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
#   SCENARIO  default: typical worst
# Prints per scenario and task `SCENARIO.TASK_instructions_per_period: N instructions` (the mean),
# `SCENARIO.TASK_instructions_max_period: N instructions (period K)` and
# `SCENARIO.TASK_instructions_median_period: N instructions`; exit 1 when valgrind is missing
# or a run fails.
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
  valgrind --tool=callgrind --collect-atstart=no --dump-instr=no --dump-line=no "${toggles[@]}" \
    '--toggle-collect=rescue::drivers::SimulatedNic::send(*' '--toggle-collect=rescue::drivers::SimulatedNic::receive(*' \
    --callgrind-out-file="$work/$scenario.out" \
    "$binary" bench wcet --scenario "$scenario" --periods "$periods" --no-plot --out "$work/$scenario-out" \
    > "$work/$scenario.log" 2> "$work/$scenario.err" || {
      status=$?
      # 2 (refused) and 3 (over budget) are verdicts of the statistics, not failed runs.
      [ "$status" -eq 2 ] || [ "$status" -eq 3 ] || { echo "instructions: $scenario run failed:" >&2; tail -5 "$work/$scenario.err" >&2; exit 1; }
    }
  # Each dump: its trigger (`Client Request: TASK`) and its total, in dump order; per task the
  # largest (and at which of its periods) and the median.
  ls "$work" | grep -E "^$scenario\.out\.[0-9]+$" | sort -t. -k3 -n | sed "s|^|$work/|" |
    /usr/bin/python3 -c '
import sys
scenario, tasks = sys.argv[1], sys.argv[2].split()
counts = {t: [] for t in tasks}
for path in sys.stdin.read().split():
    trigger, total = "", None
    with open(path) as f:
        for line in f:
            if line.startswith("desc: Trigger:"):
                trigger = line
            elif line.startswith(("totals:", "summary:")):
                total = int(line.split()[1])
    task = trigger.rsplit(":", 1)[-1].strip()
    if task in counts and total is not None:
        counts[task].append(total)
for t in tasks:
    c = counts[t][1:]  # period 0 left out: the first dump also holds the bring-up NIC toggles
    if not c:
        print(f"{scenario}.{t}_instructions_per_period: n/a (not driven)")
        continue
    k = max(range(len(c)), key=c.__getitem__)
    print(f"{scenario}.{t}_instructions_per_period: {sum(c) // len(c)} instructions")
    print(f"{scenario}.{t}_instructions_max_period: {c[k]} instructions (period {k + 1})")
    print(f"{scenario}.{t}_instructions_median_period: {sorted(c)[len(c) // 2]} instructions")
 ' "$scenario" "${tasks[*]}"
  rm -f "$work/$scenario.out".*
done
