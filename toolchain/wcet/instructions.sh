#!/usr/bin/env bash
# Instructions per period of each real-time task in each of bench wcet's scenarios, counted by
# valgrind's callgrind (docs/timing.md "Worst-path scenarios"): a figure that does not depend on the
# machine's load, so the worst path's extra work is known by construction, beside the typical
# period's. One run of `rescue-motion bench wcet --scenario S --no-plot` per scenario, collecting
# only inside the four measured period functions (wcet_*_period); the handler's figure leaves out
# the simulated NIC, which stands in for the wire. The figure is the mean over the measured periods
# (callgrind counts totals; bring-up and settling run outside those functions), not the heaviest
# period's count.
#
# Usage: toolchain/wcet/instructions.sh [BINARY] [PERIODS] [SCENARIO...]
#   BINARY    default build/release/rescue-motion
#   PERIODS   measured periods per scenario, default 2000 (bench wcet's least)
#   SCENARIO  default: typical worst
# Prints `SCENARIO.TASK_instructions_per_period: N instructions` lines; exit 1 when valgrind is
# missing or a run fails.
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

# inclusive FUNCTION: its inclusive count in the annotated profile (0 when it never ran).
inclusive() { awk -v f="$1" 'index($0, f) {gsub(",", "", $1); print $1; exit}' "$work/$scenario.txt" | sed 's/^$/0/'; }

echo "instructions_periods: $periods periods per scenario (mean per period)"
echo "instructions_valgrind: $(valgrind --version)"
for scenario in "${scenarios[@]}"; do
  # bench wcet's statistics run afterwards in a child (python3), which valgrind does not follow.
  valgrind --tool=callgrind --collect-atstart=no \
    '--toggle-collect=rescue::app::wcet_handler_period*' '--toggle-collect=rescue::app::wcet_joint_manager_period*' \
    '--toggle-collect=rescue::app::wcet_message_parser_period*' '--toggle-collect=rescue::app::wcet_rc_period*' \
    --callgrind-out-file="$work/$scenario.out" \
    "$binary" bench wcet --scenario "$scenario" --periods "$periods" --no-plot --out "$work/$scenario-out" \
    > "$work/$scenario.log" 2> "$work/$scenario.err" || {
      status=$?
      # 2 (refused) and 3 (over budget) are verdicts of the statistics, not failed runs.
      [ "$status" -eq 2 ] || [ "$status" -eq 3 ] || { echo "instructions: $scenario run failed:" >&2; tail -5 "$work/$scenario.err" >&2; exit 1; }
    }
  callgrind_annotate --inclusive=yes --threshold=100 "$work/$scenario.out" > "$work/$scenario.txt"
  handler=$(( $(inclusive 'rescue::app::wcet_handler_period') - $(inclusive 'rescue::drivers::SimulatedNic::send(') \
              - $(inclusive 'rescue::drivers::SimulatedNic::receive(') ))
  echo "$scenario.ethercat_handler_instructions_per_period: $(( handler / periods )) instructions"
  echo "$scenario.joint_manager_instructions_per_period: $(( $(inclusive 'rescue::app::wcet_joint_manager_period') / periods )) instructions"
  echo "$scenario.message_parser_instructions_per_period: $(( $(inclusive 'rescue::app::wcet_message_parser_period') / periods )) instructions"
  echo "$scenario.rc_tasks_instructions_per_period: $(( $(inclusive 'rescue::app::wcet_rc_period') / periods )) instructions"
done
