#!/usr/bin/env bash
# Instructions per period of the firmware's real-time tasks, counted by valgrind's callgrind: a
# figure that does not depend on the machine's load or clock, so a regression shows as a number
# (docs/timing.md). Runs `rescue-motion bench periods` (the tasks as `run` wires them, on the
# simulated robot in virtual time: deterministic) once per task, collecting only inside the task's
# period function; the simulated NIC (which stands in for the wire) is excluded from the handler's.
#
# Usage: toolchain/instructions.sh [BINARY] [PERIODS]
#   BINARY   default build/release/rescue-motion (the flags of the binary run.sh starts)
#   PERIODS  measured periods, default 200 (the count per period is exact for any number)
# Prints `key: value unit` lines; exit status 1 when valgrind is missing or a run fails.
set -euo pipefail
cd "$(dirname "$0")/.."
binary=${1:-build/release/rescue-motion}
periods=${2:-200}
command -v valgrind >/dev/null || { echo "instructions: valgrind not installed (toolchain/setup.sh)"; exit 1; }
[ -x "$binary" ] || { echo "instructions: $binary missing (cmake --build --preset release)"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# count TASK FUNCTION [EXCLUDED...]: instructions executed inside FUNCTION (collection is on only
# there, --toggle-collect), less those inside the EXCLUDED functions it calls (their inclusive cost
# in the same profile, which can only have been collected inside FUNCTION).
count() {
  local task=$1 function=$2; shift 2
  valgrind --tool=callgrind --collect-atstart=no "--toggle-collect=$function" --callgrind-out-file="$work/$task.out" \
    "$binary" bench periods --cycles "$periods" > "$work/$task.log" 2> "$work/$task.err" ||
    { echo "instructions: $task run failed:" >&2; tail -5 "$work/$task.err" >&2; exit 1; }
  callgrind_annotate --inclusive=yes --threshold=100 "$work/$task.out" > "$work/$task.txt"
  local total excluded=0 e
  total=$(awk '/PROGRAM TOTALS/ {gsub(",", "", $1); print $1; exit}' "$work/$task.txt")
  for e in "$@"; do
    e=$(awk -v f="$e" 'index($0, f) {gsub(",", "", $1); print $1; exit}' "$work/$task.txt")
    excluded=$((excluded + ${e:-0}))
  done
  echo "$((total - excluded)) $total"
}

# The simulated NIC stands in for the wire: the simulated robot's work is not the handler's.
read -r handler handler_with_sim < <(count ethercat 'rescue::app::measured_handler_period*' \
  'rescue::drivers::SimulatedNic::send(' 'rescue::drivers::SimulatedNic::receive(')
read -r manager _ < <(count joint_manager 'rescue::app::measured_joint_manager_step*')
read -r rc _ < <(count rc 'rescue::app::measured_rc_period*')

echo "instructions_periods: $periods periods"
echo "instructions_valgrind: $(valgrind --version)"
echo "instructions_binary: $binary"
echo "ethercat_handler_instructions_per_period: $((handler / periods)) instructions"
echo "ethercat_handler_with_simulated_robot_instructions_per_period: $((handler_with_sim / periods)) instructions"
echo "joint_manager_instructions_per_period: $((manager / periods)) instructions"
echo "rc_instructions_per_period: $((rc / periods)) instructions"
