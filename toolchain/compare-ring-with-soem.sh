#!/usr/bin/env bash
# SOEM 1.4.0's cable redundancy and ours side by side (issue 34 item 4, docs/redundancy.md "Side by
# side with SOEM"): one `rescue-motion sim --iface rga1 --ring-iface rgb1` (the robot's ring
# configuration) on two veth pairs, the master's main port on rga0 and its ring port on rgb0. Each
# side in turn: the master brings the ring up, then CABLE (a slave's name: the cable into it; or
# `ring`: the ring-return cable) is cut BREAK_S seconds after the master reached OP and restored at
# REPAIR_S (the simulator's fault commands on its standard input), and the master runs to SECONDS.
#   SOEM  toolchain/soem/soem_ring_cycle.c (ec_init_redundant, ec_config_map, ec_configdc, 1 ms
#         cycles): its own count of cycles with the full working counter, the largest |0x092C| before
#         the break, from 100 ms after it to the repair, from 100 ms after the repair, slaves not in
#         OP at the end.
#   ours  `rescue-motion run --nic raw:rga0 --ring-nic raw:rgb0 --duration SECONDS`: the end-of-run
#         figures (cycles, joints lost, joint-cycles missed by joints never lost: "healthy joints
#         missed"), the ring's reports (each break and repair, with its place).
#   both  the simulator's true clock offsets (its console's `clocks`, about every 20 ms): the largest
#         offset from position 0 before the break, from 100 ms after it, from 100 ms after the repair,
#         and the largest move of any slave's offset against the cut's instant (a SYNC0 edge moved).
# A figure a side does not give is printed as n/a.
#
# usage: toolchain/compare-ring-with-soem.sh RESCUE_MOTION_BINARY [RUNS] [CABLE]   (root; RUNS 3, CABLE r_elbow)
# environment: ANCHORS (default ../shared/anchors beside this tree), SOEM_BUILD (default
#   /tmp/soem-anchor, shared with compare-with-soem.sh), BREAK_S (2), REPAIR_S (5), SECONDS_RUN (8).
# Timing figures depend on the machine's load: run it on a quiet machine.
set -euo pipefail
bin=$(readlink -f "$1"); runs=${2:-3}; cable=${3:-r_elbow}
break_s=${BREAK_S:-2} repair_s=${REPAIR_S:-5} seconds=${SECONDS_RUN:-8}
here=$(cd "$(dirname "$0")" && pwd)
anchors=$(readlink -f "${ANCHORS:-$here/../../shared/anchors}")
work=${SOEM_BUILD:-/tmp/soem-anchor}
src=$work/SOEM-1.4.0
if [[ ! -f $src/build/libsoem.a ]]; then  # as compare-with-soem.sh builds it
  mkdir -p "$work" && tar -xzf "$anchors/soem-1.4.0.tar.gz" -C "$work"
  sed -i 's/ -Werror//' "$src/CMakeLists.txt"
  cmake -S "$src" -B "$src/build" -DCMAKE_BUILD_TYPE=Release >/dev/null && cmake --build "$src/build" -j2 >/dev/null
fi
cc -O2 -I"$src/soem" -I"$src/osal" -I"$src/osal/linux" -I"$src/oshw/linux" "$here/soem/soem_ring_cycle.c" \
   "$src/build/libsoem.a" -lpthread -lrt -o "$work/soem_ring_cycle"

tmp=$(mktemp -d /tmp/compare-ring.XXXXXX)
[[ -n ${KEEP_OUTPUT:-} ]] && mkdir -p "$KEEP_OUTPUT"
sim=""
cleanup() {
  { exec 7>&-; } 2>/dev/null || true
  [[ -n $sim ]] && kill "$sim" 2>/dev/null
  ip link del rga0 2>/dev/null || true
  ip link del rgb0 2>/dev/null || true
  if [[ -n ${KEEP_OUTPUT:-} ]]; then cp "$tmp"/*.out "$KEEP_OUTPUT"/ 2>/dev/null || true; fi
  rm -rf "$tmp"
}
trap cleanup EXIT
ip link del rga0 2>/dev/null || true
ip link del rgb0 2>/dev/null || true
ip link add rga0 type veth peer name rga1 && ip link add rgb0 type veth peer name rgb1
for i in rga0 rga1 rgb0 rgb1; do ip link set "$i" up; done

# start_sim: a fresh simulator (every side starts from the same robot), its commands from fd 7.
start_sim() {
  { exec 7>&-; } 2>/dev/null || true
  [[ -n $sim ]] && { kill "$sim" 2>/dev/null; wait "$sim" 2>/dev/null || true; }
  rm -f "$tmp/commands" && mkfifo "$tmp/commands"
  "$bin" sim --iface rga1 --ring-iface rgb1 <"$tmp/commands" >"$tmp/sim.log" 2>&1 & sim=$!
  exec 7>"$tmp/commands"
  sleep 1
}
# sample_clocks PHASE SECONDS: the simulator's true clock offsets (`clocks PHASE:MS`, MS the ms since
# the phase began) about every 20 ms for SECONDS: what a drive's SYNC0 edge follows, for both sides
# alike (SOEM's 0x092C reads saturate on the ring, and `run` reads none).
sample_clocks() {
  local start now until
  start=$(date +%s%N); until=$((start + $(awk -v s="$2" 'BEGIN {printf "%d", s * 1000}') * 1000000))  # mawk's %d stops at 2^31
  while now=$(date +%s%N); ((now < until)); do echo "clocks $1:$(((now - start) / 1000000))" >&7; sleep 0.02; done
}
# break_and_repair OUTPUT MARK: once OUTPUT shows MARK (the master is in OP), cut CABLE at BREAK_S and
# restore it at REPAIR_S, sampling the clocks throughout and 2 s past the repair. The offsets at the
# cut are asked in the same write as the cut, so the simulator answers them just before it cuts.
break_and_repair() {
  local waited=0
  until grep -q "$2" "$1" 2>/dev/null; do sleep 0.05; waited=$((waited + 1)); [[ $waited -gt 400 ]] && return 0; done
  sample_clocks before "$break_s"
  printf 'clocks at_cut:0\ncut %s\n' "$cable" >&7
  sample_clocks broken "$(awk -v a="$repair_s" -v b="$break_s" 'BEGIN {print a - b}')"
  printf 'restore %s\n' "$cable" >&7
  sample_clocks repaired 2
}
# clock_figures PREFIX: from the simulator's log, over every slave (position 0 is the reference):
# the largest true offset before the break, from 100 ms after it to the repair, and from 100 ms after
# the repair; and the largest move of any slave's offset against its offset at the cut, while broken
# and after the repair (item 3's "no SYNC0 edge moved by more than 1 us").
clock_figures() {
  awk -v p="$1" '
    function absv(x) { return x < 0 ? -x : x }
    $1 == "clocks" {
      split($2, t, ":"); phase = t[1]; ms = t[2] + 0; worst = 0; moved = 0
      for (i = 3; i <= NF; i++) {
        o = $i + 0; if (absv(o) > worst) worst = absv(o)
        if (phase == "at_cut") cut[i] = o
        else if (have_cut && absv(o - cut[i]) > moved) moved = absv(o - cut[i])
      }
      if (phase == "at_cut") have_cut = 1
      if (phase == "before") { n_before++; if (worst > before) before = worst }
      if (phase == "broken") { n_broken++; if (moved > moved_broken) moved_broken = moved
                               if (ms >= 100) { n_broken100++; if (worst > broken) broken = worst } }
      if (phase == "repaired") { n_repaired++; if (moved > moved_repaired) moved_repaired = moved
                                 if (ms >= 100) { n_repaired100++; if (worst > repaired) repaired = worst } } }
    function line(key, value, n) { if (n > 0) printf "%s%s: %d ns (%d samples)\n", p, key, value, n; else printf "%s%s: n/a (no sample)\n", p, key }
    END {
      line("dc_true_max_offset_before_break", before, n_before)
      line("dc_true_max_offset_after_break_100ms", broken, n_broken100)
      line("dc_true_max_offset_after_repair_100ms", repaired, n_repaired100)
      line("sync0_moved_max_while_broken", moved_broken, have_cut ? n_broken : 0)
      line("sync0_moved_max_after_repair", moved_repaired, have_cut ? n_repaired : 0)
    }' "$tmp/sim.log"
}
field() { awk -v k="$2:" '$1 == k {print $2; found = 1; exit} END {if (!found) print "n/a"}' "$1"; }
# rest: the whole value after the key (a DC figure is `N ns`, `saturated (...)` or `n/a (no read)`).
rest() { awk -v k="$2:" '$1 == k {sub(/^[^:]*: */, ""); print; found = 1; exit} END {if (!found) print "n/a"}' "$1"; }

for ((r = 1; r <= runs; r++)); do
  start_sim
  break_and_repair "$tmp/soem.out" "^op: yes" & schedule=$!
  "$work/soem_ring_cycle" rga0 rgb0 $((seconds * 1000)) "$break_s" "$repair_s" >"$tmp/soem.out" 2>&1 || true
  wait "$schedule" || true
  echo "run${r}_soem_op: $(field "$tmp/soem.out" op)"
  echo "run${r}_soem_cycles_full_wkc: $(field "$tmp/soem.out" cycles_full_wkc) of $((seconds * 1000))"
  echo "run${r}_soem_cycles_without_full_wkc: $(field "$tmp/soem.out" cycles_without_full_wkc)"
  echo "run${r}_soem_dc_max_abs_before_break: $(rest "$tmp/soem.out" dc_max_abs_before_break)"
  echo "run${r}_soem_dc_max_abs_after_break_100ms: $(rest "$tmp/soem.out" dc_max_abs_after_break_100ms)"
  echo "run${r}_soem_dc_max_abs_after_repair_100ms: $(rest "$tmp/soem.out" dc_max_abs_after_repair_100ms)"
  echo "run${r}_soem_slaves_not_op_at_end: $(field "$tmp/soem.out" slaves_not_op_at_end)"
  clock_figures "run${r}_soem_"
  cp "$tmp/sim.log" "$tmp/sim-soem.log"

  start_sim
  state=$(mktemp -d "$tmp/state.XXXXXX")
  break_and_repair "$tmp/ours.out" "network in OP" & schedule=$!
  "$bin" run --nic raw:rga0 --ring-nic raw:rgb0 --duration "$seconds" --state-dir "$state" >"$tmp/ours.out" 2>&1 || true
  wait "$schedule" || true
  if grep -q "network in OP" "$tmp/ours.out"; then echo "run${r}_rescue_op: yes"; else echo "run${r}_rescue_op: no"; fi
  echo "run${r}_rescue_cycles: $(field "$tmp/ours.out" periods_run)"
  echo "run${r}_rescue_joints_lost: $(grep -c "link lost" "$tmp/ours.out" || true) link-lost reports"
  missed=$(grep -oE "healthy joints missed [0-9]+ cycles" "$tmp/ours.out" | awk '{print $4}' || true)
  echo "run${r}_rescue_joint_cycles_missed: ${missed:-n/a}"
  echo "run${r}_rescue_ring_reports: $(grep -c "ethercat: ring" "$tmp/ours.out" || true)"
  grep "ethercat: ring" "$tmp/ours.out" | sed "s/^/run${r}_rescue_ring_report: /" || true
  grep -E "bring-up failed" "$tmp/ours.out" | sed "s/^/run${r}_rescue_/" || true
  late=$(grep -oE "frames late or lost: [0-9]+" "$tmp/ours.out" | awk '{print $5}' || true)
  echo "run${r}_rescue_frames_late_or_lost: ${late:-n/a}"
  repeats=$(grep -oE "^ring_repeats: [0-9]+" "$tmp/ours.out" | awk '{print $2}' || true)
  echo "run${r}_rescue_ring_repeats: ${repeats:-n/a}"
  clock_figures "run${r}_rescue_"
  # Every run's output is kept (the last run's also under the names without the run's number).
  if [[ -n ${KEEP_OUTPUT:-} ]]; then
    cp "$tmp/ours.out" "$KEEP_OUTPUT/run${r}-ours.out" 2>/dev/null || true
    cp "$tmp/soem.out" "$KEEP_OUTPUT/run${r}-soem.out" 2>/dev/null || true
    cp "$tmp/sim-soem.log" "$KEEP_OUTPUT/run${r}-sim-soem.log" 2>/dev/null || true
    cp "$tmp/sim.log" "$KEEP_OUTPUT/run${r}-sim-ours.log" 2>/dev/null || true
  fi
done
