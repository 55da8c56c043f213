#!/usr/bin/env bash
# The EtherCAT handler's instructions per period in `run`'s scenarios, counted by valgrind's callgrind
# as toolchain/wcet/instructions.sh counts bench wcet's (docs/timing.md "The heaviest handler
# scenario against every other run"): collection on only inside the handler's period (its cycle,
# run_handler_cycle, and the publication of the master's figures, run_handler_publish, which dumps the
# counters at its end: core/app/tasks/period_mark.hpp), the simulated NIC's send and receive left out
# (they stand in for the wire, as in bench wcet). Instructions do not depend on the machine's load or
# on valgrind's slowness; which paths a run takes does: under valgrind the wall-clock run is some 50
# times slower, its periods overrun (the master skips periods to keep its phase), so a scenario's
# periods under callgrind are fewer than on the wall clock and its late frames may take paths a
# native run does not.
#
# Usage: toolchain/wcet/run-instructions.sh [BINARY] [SECONDS] [SCENARIO...]
#   BINARY    default build/release/rescue-motion
#   SECONDS   run --duration, default 12 (the scenarios act 1 s after OP)
#   SCENARIO  a run --scenario name, or ring:NAME for the ring (--ring-nic sim); default: rescue
#             link-cut power-cycle flaky-cable cable-damage half-mapped foreign-mapping ring:link-cut
# Run it under the machine's serial lock (`flock /tmp/rescue-serial.lock ...`): each scenario is a
# firmware instance. Prints per scenario `run.SCENARIO.ethercat_handler_instructions_max_period: N
# instructions (period K)`, `..._median_period`, `..._periods` and the run's exit status; exit 1 when
# valgrind is missing or a run gives no period.
set -euo pipefail
cd "$(dirname "$0")/../.."
binary=${1:-build/release/rescue-motion}
seconds=${2:-12}
shift $(( $# > 2 ? 2 : $# ))
scenarios=("$@")
[ "${#scenarios[@]}" -gt 0 ] || scenarios=(rescue link-cut power-cycle flaky-cable cable-damage half-mapped foreign-mapping ring:link-cut)
command -v valgrind >/dev/null || { echo "run-instructions: valgrind not installed (toolchain/setup.sh)"; exit 1; }
[ -x "$binary" ] || { echo "run-instructions: $binary missing (cmake --build build/release --target rescue-motion)"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "run_instructions_seconds: $seconds s of run --threads per scenario under callgrind"
echo "run_instructions_valgrind: $(valgrind --version)"
for entry in "${scenarios[@]}"; do
  scenario=${entry#ring:}
  ring=()
  [ "$entry" = "$scenario" ] || ring=(--nic sim --ring-nic sim)
  name=${entry/:/_}
  mkdir -p "$work/$name-state"
  status=0
  valgrind --tool=callgrind --collect-atstart=no --dump-instr=no --dump-line=no \
    '--toggle-collect=rescue::app::runner::run_handler_cycle*' '--toggle-collect=rescue::app::runner::run_handler_publish*' \
    '--toggle-collect=rescue::drivers::SimulatedNic::send(*' '--toggle-collect=rescue::drivers::SimulatedNic::receive(*' \
    --callgrind-out-file="$work/$name.out" \
    "$binary" run --threads "${ring[@]}" --duration "$seconds" --scenario "$scenario" --initialize --auto-clear-power-cycled \
    --state-dir "$work/$name-state" --segment "/rescue-wcet-run-$$" > "$work/$name.log" 2> "$work/$name.err" || status=$?
  echo "run.$name.exit_status: $status"
  ls "$work" | grep -E "^$name\.out\.[0-9]+$" | sort -t. -k3 -n | sed "s|^|$work/|" |
    /usr/bin/python3 toolchain/wcet/callgrind_periods.py "run.$name" ethercat_handler || { echo "run-instructions: $entry gave no handler period:" >&2; tail -5 "$work/$name.err" >&2; exit 1; }
  grep -E "max_execution_ns_ethercat|recovered|lost" "$work/$name.log" | head -5 | sed "s|^|run.$name.log: |"
  find "$work" -maxdepth 1 -name "$name.out.*" -delete  # one dump a period: too many for rm's arguments
done
