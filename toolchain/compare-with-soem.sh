#!/usr/bin/env bash
# SOEM 1.4.0 and our master side by side on one veth pair against one `rescue-motion sim`, in one
# command, every figure as a `key: value` line of both sides measured the same way (docs/timing.md
# "Side by side with SOEM"). Our own copy of the anchor's method (../shared/anchors/compare-with-soem.sh,
# which stays as it is): SOEM is built from the anchor's tarball and soem_cycle.c exactly as it builds
# them, the simulator is started the same way (COMPARE_SIM_CPU below), and each program runs for 2000
# and for 12000 cycles so that start-up cancels out:
#   valid cycles            SOEM: cycles_full_wkc; ours: cycles_all_joints_valid (the 12000-cycle run),
#                           every joint valid in its period; and, counted as SOEM's test counts (its
#                           frame back with the full working counter within 2 ms, EC_TIMEOUTRET,
#                           whatever the period), cycles_valid_within_2ms as *_valid_cycles_as_soem_counts
#   send+receive median     SOEM: soem_cycle_wall_median; ours: nic_time_median (the 12000-cycle run)
#   process CPU per cycle   (user+sys of the 12000-cycle run - of the 2000-cycle run) / 10000
#   time to OP              wall of the 2000-cycle run - 2000 x (wall(12000) - wall(2000)) / 10000:
#                           start-up, bring-up to OP and exit, the same for both programs
#   wall time               of the 2000-cycle run
# Ours also prints its in-process bring_up_to_op (bench master's own clock). Our master keeps its
# SII cache in a directory as `run` does in its state directory: one unmeasured run fills it first
# (its bring-up with the cache cold is printed as rescue_cold_sii_bring_up_to_op_ms), and the measured
# runs find it warm, as every start of the robot after its first does. SOEM has no such cache.
#
# usage: toolchain/compare-with-soem.sh RESCUE_MOTION_BINARY [RUNS]   (root; RUNS default 3)
# environment: ANCHORS (default ../shared/anchors beside this tree), SOEM_BUILD (default /tmp/soem-anchor,
#   shared with the anchor's script), COMPARE_VETH (veth name prefix, default vcmp: vcmp0 and vcmp1),
#   COMPARE_SIM_CPU (the simulator's CPU: default `sim`'s own, the EtherCAT task's; `any`: the scheduler's).
# Timing figures depend on the machine's load: run it on a quiet machine, and take a shared machine's
# figures as measured under load.
set -euo pipefail
bin=$(readlink -f "$1"); runs=${2:-3}
here=$(cd "$(dirname "$0")" && pwd)
anchors=$(readlink -f "${ANCHORS:-$here/../../shared/anchors}")
work=${SOEM_BUILD:-/tmp/soem-anchor}
short=2000 long=12000
if [[ ! -x $work/soem_cycle ]]; then  # as the anchor's script builds it
  mkdir -p "$work" && tar -xzf "$anchors/soem-1.4.0.tar.gz" -C "$work"
  src=$work/SOEM-1.4.0; sed -i 's/ -Werror//' "$src/CMakeLists.txt"
  cmake -S "$src" -B "$src/build" -DCMAKE_BUILD_TYPE=Release >/dev/null && cmake --build "$src/build" -j2 >/dev/null
  cc -O2 -I"$src/soem" -I"$src/osal" -I"$src/osal/linux" -I"$src/oshw/linux" "$anchors/soem_cycle.c" \
     "$src/build/libsoem.a" -lpthread -lrt -o "$work/soem_cycle"
fi
prefix=${COMPARE_VETH:-vcmp}; a=${prefix}0 b=${prefix}1
cache=$(mktemp -d /tmp/compare-sii-cache.XXXXXX)
ip link del "$a" 2>/dev/null || true
ip link add "$a" type veth peer name "$b" && ip link set "$a" up && ip link set "$b" up
sim=""; trap '[[ -n $sim ]] && kill $sim 2>/dev/null; ip link del $a 2>/dev/null || true; rm -rf "$cache"' EXIT
# The simulator stands for the NIC and the slaves: by its own default on the EtherCAT task's CPU, as
# docs/deploy.md puts the NIC's interrupt ("NIC interrupt on the handler's CPU"), so its replies are
# delivered on that CPU; the anchor's script starts it the same way. COMPARE_SIM_CPU=any (`sim --cpu
# any`) leaves it to the scheduler, N puts it on CPU N (docs/timing.md has both).
sim_cpu=${COMPARE_SIM_CPU:-}
cpu_option=(); [[ -n $sim_cpu ]] && cpu_option=(--cpu "$sim_cpu")
echo "simulator_cpu: ${sim_cpu:-the EtherCAT task's (sim's default)}"
"$bin" sim --iface "$b" "${cpu_option[@]}" >/dev/null 2>&1 & sim=$!
sleep 1

out=$(mktemp /tmp/compare-run.XXXXXX)
# timed COMMAND...: runs it, leaves its output in $out and sets wall_ns, cpu_s.
timed() {
  local t0 t1
  t0=$(date +%s%N)
  /usr/bin/time -f "process_cpu_s: %U %S" -o "$out.time" "$@" >"$out" 2>&1 || { cat "$out" >&2; return 1; }
  t1=$(date +%s%N)
  wall_ns=$((t1 - t0))
  cpu_s=$(awk '{print $2 + $3}' "$out.time")
}
field() { awk -v k="$1:" '$1 == k {print $2; exit}' "$out"; }
ms() { awk -v x="$1" 'BEGIN {printf "%.1f", x / 1e6}'; }

ours=("$bin" bench master --nic "raw:$a" --cold-start no --sii-cache-dir "$cache" --cycles)
timed "${ours[@]}" 100
echo "rescue_cold_sii_bring_up_to_op_ms: $(field bring_up_to_op) (SII cache empty: every image read)"

for ((r = 1; r <= runs; r++)); do
  for side in soem rescue; do
    if [[ $side == soem ]]; then cmd=("$work/soem_cycle" "$a"); else cmd=("${ours[@]}"); fi
    timed "${cmd[@]}" "$short"; w_short=$wall_ns c_short=$cpu_s
    timed "${cmd[@]}" "$long"; w_long=$wall_ns c_long=$cpu_s
    if [[ $side == soem ]]; then
      valid=$(field cycles_full_wkc); sendrecv=$(field soem_cycle_wall_median)
    else
      valid=$(field cycles_all_joints_valid); sendrecv=$(field nic_time_median)
      own_op=$(field bring_up_to_op); as_soem=$(field cycles_valid_within_2ms)
    fi
    per_cycle_wall=$(((w_long - w_short) / (long - short)))
    to_op=$((w_short - short * per_cycle_wall))
    cpu_us=$(awk -v a="$c_long" -v b="$c_short" -v n=$((long - short)) 'BEGIN {printf "%.1f", (a - b) * 1e6 / n}')
    echo "run${r}_${side}_valid_cycles: $valid of $long"
    echo "run${r}_${side}_send_receive_median_us: $sendrecv"
    echo "run${r}_${side}_process_cpu_per_cycle_us: $cpu_us"
    echo "run${r}_${side}_time_to_op_ms: $(ms "$to_op")"
    echo "run${r}_${side}_wall_time_${short}_cycles_ms: $(ms "$w_short")"
    [[ $side == rescue ]] && echo "run${r}_rescue_valid_cycles_as_soem_counts: $as_soem of $long"
    [[ $side == rescue ]] && echo "run${r}_rescue_own_bring_up_to_op_ms: $own_op"
  done
done
rm -f "$out" "$out.time"
