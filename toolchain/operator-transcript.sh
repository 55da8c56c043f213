#!/usr/bin/env bash
# Runs every example of docs/operator.md against the program and checks that the page still says what
# the program does; with --write, rewrites the page's example outputs instead. Starts `rescue-motion
# run` on the simulated robot (default processes mode, a temporary state directory, its own key made
# by `ctl keygen`, free UDP ports of 127.0.0.1), runs every `ctl` verb against it in the order an
# operator would (and a refused command of each reachable kind), then a second short run with
# `--scenario link-cut` for the unreachable-joint refusals and the graph of a cut, and a third with
# `--scenario cable-damage` for `ctl diag` with a damaged cable and its reset, and a fourth with
# `--scenario power-cycle` for `ctl states` of a drive out of service. Each section NAME of the
# transcript belongs to the block
#   <!-- BEGIN TRANSCRIPT NAME -->
#   ...
#   <!-- END TRANSCRIPT NAME -->
# of docs/operator.md. The prose around the blocks is left alone.
# Every command must end as the page says (ctl's exit statuses, docs/operator.md "Exit status"): a ctl
# without --refused or --usage must exit 0, one with --refused 1 (refused), one with --usage 2 (a bad
# argument); ctl_raw names the status it expects; otherwise the script fails (exit 1) and the page is
# not rewritten. Then the examples of
# docs/firmware.md run (the link-cut, power-cycle with and without the automatic clear, and
# cable-damage scenarios) and each must exit 0.
# Check (the default): each block must equal its section but for the volatile figures: both are
# normalised (every decimal number -> '#'; the program's version, build type, layout hash and segment name; the
# scheduling policy the kernel granted; a status row's OWNER and a JSON joint's owner, which are the
# last period's; runs of blanks -> one blank; a line cut by --cut compared up to the shorter of the
# two; the lines a run logs, from several processes at once, in any order) and compared; a
# difference in anything else (a word, a state, a name, a row, a line) fails with a unified diff of
# the normalised block, and the runs' logs are kept. The page is never written in this mode.
# --write: the blocks are replaced by this run's sections (after a code change that alters an output).
# Usage: bash toolchain/operator-transcript.sh [--write] [BUILD_DIR]   (default build/debug; built)
# Takes about 60 s; run it under the serial lock (flock /tmp/rescue-serial.lock) on a shared machine.
set -euo pipefail
cd "$(dirname "$0")/.."
mode=check
if [ "${1:-}" = "--write" ]; then mode=write; shift; fi
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
mkdir -p "$dir/sections" "$dir/link-cut" "$dir/cable-damage" "$dir/power-cycle"
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
      --usage) wanted=2; shift ;;
      *) break ;;
    esac
  done
  local out status=0
  out="$("$program" ctl --key "$key" --port "$control_port" "$@" 2>&1)" || status=$?
  expect "$status" "$wanted" "ctl $*"
  [ "$status" -eq "$wanted" ] || printf '%s\n' "$out" | sed 's/^/    /' >&2
  [ -n "$rows" ] && { out="$(printf '%s\n' "$out" | awk -v re="$rows" 'NR <= 2 || $0 ~ re')"; note="  (rows: $rows)"; }
  [ -n "$cut" ] && { out="$(printf '%s\n' "$out" | cut -c "1-$cut")..."; note="  (first $cut characters)"; }
  [ "$status" -ne 0 ] && out="$out"$'\n'"(exit status $status)"
  printf '%s\n' "$out" | emit "rescue-motion ctl $*$note"
}
# ctl_raw STATUS ARGS...: like ctl, with ARGS given in full (another key, no --port), for the bad-key
# outcomes: 3 (unreachable: the robot stays silent to another key), 4 (local: a key file refused).
ctl_raw() {
  local wanted="$1" out status=0
  shift
  out="$("$program" ctl "$@" 2>&1)" || status=$?
  expect "$status" "$wanted" "ctl $*"
  [ "$status" -ne 0 ] && out="$out"$'\n'"(exit status $status)"
  printf '%s\n' "$out" | emit "rescue-motion ctl $*"
}
# Starts `rescue-motion run ARGS` in the background on $state (its output in $state/run.log) and waits for OP.
# Shows the command (the output comes with run_lines).
start_run() {
  local args=(run --state-dir "$state" --key "$key" --listen 127.0.0.1 --control-port "$control_port"
    --sensor-port "$sensor_port" "$@")
  printf '    $ rescue-motion %s &\n' "${args[*]}" | tidy >>"$section"
  : >"$state/run.log"  # there before the background run's own redirect, for the grep below
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
# The page shows the run's start-up lines up to both RC tasks' first state: waited for, not slept on.
wait_log "rc-rescue: idle"
wait_log "rc-teleop: teleop"
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
ctl upload 19 0x1008:00
ctl --refused upload junction_a 0x1018:01
ctl --refused --json upload 1 0x1018:01
begin sii
ctl sii_read junction_a
ctl --cut 200 --json sii_read neck_pan
ctl xml junction_a
ctl --rows '<Type|<Sm |Pdo |#x6040' xml l_elbow
ctl --cut 300 --json xml neck_pan
ctl reg_read l_elbow 0x0130 2
ctl reg_read junction_a 0x0000 16
ctl --json reg_read l_elbow 0x0130 6
begin rescan
ctl rescan
ctl --cut 300 --json rescan
begin network
ctl slaves -v
ctl --cut 300 --json slaves -v
ctl graph
ctl --rows 'digraph|s1[89]|^}' graph --format dot
ctl pdos l_elbow
ctl --cut 300 --json pdos l_elbow
ctl pdos 0
ctl --rows 'objects|^SDO 0x10(08|18)|0x1008:00|0x1018:0|0x6041:00' sdos l_elbow --values
ctl --cut 300 --json sdos l_elbow
ctl --refused sdos junction_a

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
ctl enable l_elbow
ctl --refused mode l_elbow csv
ctl --refused owner 3
ctl --refused move left 0.4,0.2,0.3,0,0,0 --task 2
ctl --refused move left 0.4,0.2,0.3,0,0,0 --task 1
ctl disable l_hand,r_hand
ctl --refused mode l_hand,r_hand,l_elbow csv
ctl --rows 'l_elbow|l_hand|r_hand' status
ctl --refused --json mode l_hand,l_elbow csv
ctl enable l_hand,r_hand
ctl init
ctl --usage enable l_elbow,tail

begin bad-key
"$program" ctl keygen --key "$dir/other.key" >/dev/null
ctl_raw 3 --key "$dir/other.key" --port "$control_port" --timeout 1 status
cp "$dir/other.key" "$dir/open.key" && chmod 644 "$dir/open.key"
ctl_raw 4 --key "$dir/open.key" --port "$control_port" status
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
begin graph-cut
ctl graph
begin rescan-cut
ctl --rows 'differences|missing' rescan
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
ctl diag --reset
ctl --rows 'l_shoulder_yaw|l_elbow|l_wrist_yaw|warning' diag
ctl --json diag --reset l_elbow
stop_run

begin states
state="$dir/power-cycle"
start_run --scenario power-cycle --duration 30
wait_log "link recovered: l_elbow"
ctl --refused states l_wrist_yaw PREOP
ctl states l_elbow PREOP
ctl --rows 'l_elbow' slaves -v
ctl --refused clear l_elbow
ctl --json states l_elbow OP
ctl reg_read l_elbow 0x0130 2
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
logs="${TMPDIR:-/tmp}/rescue-operator-transcript-logs"
keep_logs() {  # the runs' logs of a failed check, for its reader
  rm -rf "$logs" && mkdir -p "$logs" && cp "$dir/run.log" "$logs/session.log" && cp "$dir/link-cut/run.log" "$logs/link-cut.log" &&
    cp "$dir/cable-damage/run.log" "$logs/cable-damage.log" && cp "$dir/power-cycle/run.log" "$logs/power-cycle.log" && echo "operator-transcript: the runs' logs are in $logs" >&2
}
if [ "$failures" -ne 0 ]; then
  echo "operator-transcript: $failures command(s) did not end as the pages say; $doc not rewritten" >&2
  keep_logs
  exit 1
fi

# Check: each block against its section, normalised; --write: each block replaced by its section.
# A block without a section (or the reverse) is an error in both modes.
python3 - "$mode" "$doc" "$dir/sections" <<'PY' || { keep_logs; exit 1; }
import difflib, os, re, sys
mode, path, sections = sys.argv[1], sys.argv[2], sys.argv[3]
text = open(path).read()
made = {name: open(os.path.join(sections, name)).read() for name in os.listdir(sections)}
pattern = re.compile(r"(<!-- BEGIN TRANSCRIPT (\S+) -->\n)(.*?)(<!-- END TRANSCRIPT \2 -->)", re.S)
blocks = {m.group(2): m.group(3) for m in pattern.finditer(text)}
unknown = sorted(set(blocks) - set(made))
missing = sorted(set(made) - set(blocks))
if unknown:
    sys.exit(f"operator-transcript: {path} has blocks the script does not make: {', '.join(unknown)}")
if missing:
    sys.exit(f"operator-transcript: {path} has no block for: {', '.join(missing)}")

def normalise(line):
    line = re.sub(r"rescue-motion [^ ]+ \(", "rescue-motion VERSION (", line)       # ctl version (git describe)
    line = re.sub(r'"program":"[^"]*"', '"program":"VERSION"', line)
    line = re.sub(r"\((Debug|Release|RelWithDebInfo|MinSizeRel) build\)", "(BUILD build)", line)  # the build checked
    line = re.sub(r'"build_type":"[A-Za-z]*"', '"build_type":"BUILD"', line)
    line = re.sub(r"hash 0x[0-9a-f]+", "hash 0xHASH", line)                          # layout hash (per layout)
    line = re.sub(r'"layout_hash":"0x[0-9a-f]+"', '"layout_hash":"0xHASH"', line)
    line = re.sub(r"\b(OTHER|FIFO|RR|BATCH|IDLE)\b", "POLICY", line)                   # what the kernel granted
    line = re.sub(r"/rescue-motion-[0-9a-f]+", "/rescue-motion-SEGMENT", line)       # shared-memory segment name
    line = re.sub(r'"owner":null', '"owner":#', line)                                # owner in the last period
    line = re.sub(r"(?<![0-9A-Za-z_x])[-+]?[0-9]+(\.[0-9]+)?(e[-+]?[0-9]+)?", "#", line)  # every decimal figure
    line = re.sub(r"\s+", " ", line).strip()
    # A status row's OWNER: the RC task whose references drove the joint in the last period (or -).
    return re.sub(r"^(# [a-z_]+ .* (CSP|CSV|CST|-) # # # \S+) (rc[0-9]|-)$", r"\1 OWNER", line)

def lines_of(block):
    # The lines a run logs after a shown `run ... &` or `kill` come from several processes at once:
    # their order varies, so such a segment is compared as a sorted list.
    out, segment = [], None
    for raw in block.strip("\n").split("\n"):
        line = normalise(raw)
        if line.startswith("$ "):
            if segment is not None:
                out.extend(sorted(segment))
            out.append(line)
            segment = None if line.startswith("$ rescue-motion ctl") else []
        elif segment is not None:
            segment.append(line)
        else:
            out.append(line)
    if segment is not None:
        out.extend(sorted(segment))
    return out

if mode == "write":
    new = pattern.sub(lambda m: m.group(1) + "\n" + made[m.group(2)] + "\n" + m.group(4), text)
    if new != text:
        open(path, "w").write(new)
    print(f"operator-transcript: rewrote {len(made)} blocks of {path}")
    sys.exit(0)

differ = 0
for name in sorted(made):
    page, now = lines_of(blocks[name]), lines_of(made[name])
    # A line cut by --cut ends in "...": compared up to the shorter of the two (figures change its length).
    for i in range(min(len(page), len(now))):
        if page[i].endswith("...") and now[i].endswith("..."):
            n = min(len(page[i]), len(now[i])) - 3
            page[i], now[i] = page[i][:n], now[i][:n]
    if page != now:
        differ += 1
        sys.stderr.write(f"operator-transcript: block {name} of {path} differs from the program's output "
                         "(figures normalised to '#'):\n")
        sys.stderr.writelines(l + "\n" for l in difflib.unified_diff(
            page, now, f"{path} ({name})", f"program now ({name})", lineterm="", n=2))
if differ:
    sys.exit(f"operator-transcript: {differ} block(s) differ; if the change is intended: "
             "bash toolchain/operator-transcript.sh --write, and commit the page")
print(f"operator-transcript: {len(made)} blocks of {path} match the program (figures aside)")
PY
