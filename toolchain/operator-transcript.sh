#!/usr/bin/env bash
# Regenerates the example outputs of docs/operator.md from the program, so they cannot drift: starts
# `rescue-motion run` on the simulated robot (default processes mode, a temporary state directory, its
# own key made by `ctl keygen`, free UDP ports of 127.0.0.1), runs every `ctl` verb against it in the
# order an operator would (and a refused command of each reachable kind), then a second short run with
# `--scenario link-cut` for the unreachable-joint refusals and a third with `--scenario cable-damage`
# for `ctl diag` with a damaged cable, and rewrites each block
#   <!-- BEGIN TRANSCRIPT NAME -->
#   ...
#   <!-- END TRANSCRIPT NAME -->
# of docs/operator.md with section NAME of the transcript. The prose around the blocks is left alone.
# Every command must end as the page says: a ctl without --refused must exit 0, one with --refused must
# exit 1; otherwise the script fails (exit 1) and the page is not rewritten. Then the examples of
# docs/firmware.md run (the link-cut, power-cycle with and without the automatic clear, and
# cable-damage scenarios) and each must exit 0.
# Usage: bash toolchain/operator-transcript.sh [BUILD_DIR]   (default build/debug; the program must be built)
# Takes about 45 s. The figures (cycles, PIDs, times) are those of this run: they change every time.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build/debug}"
program="$(cd "$build" 2>/dev/null && pwd)/rescue-motion"
[ -x "$program" ] || { echo "operator-transcript: $build/rescue-motion not built"; exit 1; }
doc=docs/operator.md

dir="$(mktemp -d /tmp/rescue-operator-transcript.XXXXXX)"
run_pid=""
run_status=""
stop_run() {
  if [ -n "$run_pid" ]; then
    kill -TERM "$run_pid" 2>/dev/null || true
    run_status=0
    wait "$run_pid" 2>/dev/null || run_status=$?
    run_pid=""
  fi
}
trap 'stop_run; rm -rf "$dir"' EXIT
mkdir -p "$dir/sections" "$dir/link-cut" "$dir/cable-damage"
state="$dir"  # the state directory of the run being shown

# Two UDP ports of 127.0.0.1 free a moment ago (both held open while chosen: they differ).
read -r control_port sensor_port < <(python3 -c '
import socket
s = [socket.socket(socket.AF_INET, socket.SOCK_DGRAM) for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
key="$dir/operator.key"
section=""

# What the page shows: the state directory as D, the program as `rescue-motion`, no terminal escapes.
tidy() { sed -e "s|$dir|D|g" -e "s|$program|rescue-motion|g" -e 's/\x1b\[[0-9;]*[A-Za-z]//g'; }
# Starts section NAME (docs/operator.md's block of that name).
begin() { section="$dir/sections/$1"; : >"$section"; }
# Appends one shown command ($1, as the page prints it) and its output (stdin), indented as a code block.
emit() {
  { printf '$ %s\n' "$1"; cat; } | tidy | sed 's/^/    /' >>"$section"
}
# ctl [--rows REGEX] [--cut N] ARGS...: runs `rescue-motion ctl --key D/operator.key --port P ARGS`,
# shows `rescue-motion ctl ARGS`, its output (--rows: only the first two lines and the rows matching
# REGEX; --cut: lines cut to N characters) and its exit status when not 0.
failures=0
# expect STATUS WANTED WHAT: counts a command that did not end as the page says.
expect() {
  if [ "$1" -ne "$2" ]; then
    echo "operator-transcript: FAILED: '$3' exited $1, the page says $2" >&2
    failures=$((failures + 1))
  fi
}
ctl() {
  local rows="" cut="" note="" wanted=0
  while :; do
    case "$1" in
      --rows) rows="$2"; shift 2 ;;
      --cut) cut="$2"; shift 2 ;;
      --refused) wanted=1; shift ;;
      *) break ;;
    esac
  done
  local out status=0
  out="$("$program" ctl --key "$key" --port "$control_port" "$@" 2>&1)" || status=$?
  expect "$status" "$wanted" "ctl $*"
  [ -n "$rows" ] && { out="$(printf '%s\n' "$out" | awk -v re="$rows" 'NR <= 2 || $0 ~ re')"; note="  (rows: $rows)"; }
  [ -n "$cut" ] && { out="$(printf '%s\n' "$out" | cut -c "1-$cut")..."; note="  (first $cut characters)"; }
  [ "$status" -ne 0 ] && out="$out"$'\n'"(exit status $status)"
  printf '%s\n' "$out" | emit "rescue-motion ctl $*$note"
}
# Like ctl, with ARGS given in full (another key, no --port): for the bad-key refusals.
ctl_raw() {
  local out status=0
  out="$("$program" ctl "$@" 2>&1)" || status=$?
  expect "$status" 1 "ctl $*"
  [ "$status" -ne 0 ] && out="$out"$'\n'"(exit status $status)"
  printf '%s\n' "$out" | emit "rescue-motion ctl $*"
}
# Starts `rescue-motion run ARGS` in the background on $state (its output in $state/run.log) and waits for OP.
# Shows the command (the output comes with run_lines).
start_run() {
  local args=(run --state-dir "$state" --key "$key" --listen 127.0.0.1 --control-port "$control_port"
    --sensor-port "$sensor_port" "$@")
  printf '    $ rescue-motion %s &\n' "${args[*]}" | tidy >>"$section"
  "$program" "${args[@]}" >"$state/run.log" 2>&1 &
  run_pid=$!
  for _ in $(seq 300); do
    grep -q "network in OP" "$state/run.log" && return 0
    kill -0 "$run_pid" 2>/dev/null || break
    sleep 0.1
  done
  echo "operator-transcript: run did not reach OP:"; cat "$state/run.log"; exit 1
}
# Waits (up to 10 s) until the run's log shows $1.
wait_log() {
  for _ in $(seq 100); do grep -q "$1" "$state/run.log" && return 0; sleep 0.1; done
  echo "operator-transcript: no '$1' in the run's log:"; cat "$state/run.log"; exit 1
}
# The run's log: the lines matching $1 (for the page).
run_lines() { grep -E "$1" "$state/run.log" | tidy | sed 's/^/    /' >>"$section" || true; }

begin keygen
"$program" ctl keygen --key "$key" 2>&1 | emit "rescue-motion ctl keygen --key D/operator.key"

begin run
start_run --duration 120
sleep 0.5
run_lines '.'

begin init
ctl init
sleep 0.3
ctl status

begin queries
ctl version
ctl slaves
ctl master
sleep 1  # a second of figures
ctl tasks
ctl diag

begin sdo
ctl upload l_elbow 0x100A:00
ctl upload neck_pan 0x1008:00
ctl upload l_elbow 0x603F:00
ctl upload l_elbow 0x2002:00 --type i16
ctl --json upload l_elbow 0x100A:00
ctl download l_elbow 0x2010:00 replaced-2026-11-26,harness-B7-recrimped,encoder-offset-checked-on-the-jig
ctl --json upload l_elbow 0x2010:00
ctl download l_elbow 0x6066:00 100 --type u16
ctl --refused download l_elbow 0x607A:00 1000 --type i32
ctl --refused --json download l_elbow 0x6040:00 0x0f --type u16
ctl --refused download l_elbow 0x1C12:00 0 --type u8
ctl --refused upload l_elbow 0x5FFF:00
ctl --refused download l_elbow 0x1008:00 RM-JD403

begin joints
ctl disable l_hand
ctl --rows 'l_wrist|l_hand' status
ctl hold
ctl enable l_hand
ctl disable l_elbow
ctl mode l_elbow csv
ctl --rows 'l_elbow' status
ctl init l_elbow
ctl --rows 'l_elbow' status

begin rc
ctl owner 1
ctl hand left close --task 1
sleep 1
ctl --rows 'waist_yaw|l_hand' status
ctl owner 0
ctl move left 0.4,0.2,0.3,0,0,0 --task 0
sleep 0.5
ctl owner
ctl --json owner
ctl --rows 'waist_yaw|neck_pan|l_shoulder|l_elbow' status

begin clear
ctl --refused clear l_hand
ctl --refused clear l_hand --moved

begin json
ctl --cut 300 --json status
ctl --cut 300 --json tasks
ctl --rows 'waist_yaw|neck_pan' watch --count 1

begin refusals
ctl --refused enable l_elbow
ctl --refused mode l_elbow csv
ctl --refused owner 3
ctl --refused move left 0.4,0.2,0.3,0,0,0 --task 2
ctl --refused move left 0.4,0.2,0.3,0,0,0 --task 1
ctl disable l_hand,r_hand
ctl --refused enable l_hand,r_hand,l_elbow
ctl --rows 'l_elbow|l_hand|r_hand' status
ctl --refused --json enable l_hand,l_elbow
ctl enable l_hand,r_hand
ctl --refused enable l_elbow,tail

begin bad-key
"$program" ctl keygen --key "$dir/other.key" >/dev/null
ctl_raw --key "$dir/other.key" --port "$control_port" --timeout 1 status
cp "$dir/other.key" "$dir/open.key" && chmod 644 "$dir/open.key"
ctl_raw --key "$dir/open.key" --port "$control_port" status
ctl --rows 'rejected unauthenticated|accepted' master

begin stop
stop_run
printf '    $ kill -TERM %%1     (the run'"'"'s summary lines; its per-task and key: value lines cut)\n' >>"$section"
run_lines '^rescue-motion run: ([0-9]+ cycles|heap|datagrams|socket handler)'
printf '    (exit status %s)\n' "$run_status" >>"$section"

begin unreachable
state="$dir/link-cut"
start_run --scenario link-cut --initialize --duration 30
wait_log "link lost"
sleep 0.5
run_lines 'cut the link|link lost|reconfiguration step|--comm_lost-->'
ctl --rows 'l_shoulder_yaw|l_elbow|l_wrist|l_hand' status
ctl --refused enable l_hand
ctl --refused init l_elbow,l_hand
ctl --refused clear l_elbow
ctl --refused upload l_hand 0x603F:00
stop_run

begin diag
state="$dir/cable-damage"
start_run --scenario cable-damage --duration 30
wait_log "receive errors rising"
sleep 0.5
run_lines 'receive errors'
ctl diag
sleep 4
ctl --rows 'l_shoulder|l_elbow|l_wrist|l_hand|warning' diag
stop_run

# The examples of docs/firmware.md: each must exit 0.
for example in "--scenario link-cut" "--scenario power-cycle --duration 4" \
               "--scenario power-cycle --duration 4 --auto-clear-power-cycled" "--scenario cable-damage --duration 3"; do
  rm -rf "$dir/firmware"
  status=0
  # shellcheck disable=SC2086  # the example's words
  "$program" run $example --state-dir "$dir/firmware" >"$dir/firmware.log" 2>&1 || status=$?
  expect "$status" 0 "run $example (docs/firmware.md)"
  [ "$status" -eq 0 ] || tail -n 5 "$dir/firmware.log" >&2
done
if [ "$failures" -ne 0 ]; then
  echo "operator-transcript: $failures command(s) did not end as the pages say; $doc not rewritten" >&2
  exit 1
fi

# Rewrites each block of the page with its section; a block without a section (or the reverse) is an error.
python3 - "$doc" "$dir/sections" <<'PY'
import os, re, sys
path, sections = sys.argv[1], sys.argv[2]
text = open(path).read()
made = {name: open(os.path.join(sections, name)).read() for name in os.listdir(sections)}
pattern = re.compile(r"(<!-- BEGIN TRANSCRIPT (\S+) -->\n)(.*?)(<!-- END TRANSCRIPT \2 -->)", re.S)
used = set()
def regenerate(m):
    name = m.group(2)
    if name not in made:
        sys.exit(f"operator-transcript: {path} has a block {name} the script does not make")
    used.add(name)
    return m.group(1) + "\n" + made[name] + "\n" + m.group(4)
new = pattern.sub(regenerate, text)
missing = sorted(set(made) - used)
if missing:
    sys.exit(f"operator-transcript: {path} has no block for: {', '.join(missing)}")
if new != text:
    open(path, "w").write(new)
print(f"operator-transcript: rewrote {len(used)} blocks of {path}")
PY
