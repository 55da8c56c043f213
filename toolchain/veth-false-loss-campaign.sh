#!/usr/bin/env bash
# Issue 11 closing figures (not run in CI; root): false joint losses of `rescue-motion run --nic raw:`
# against `rescue-motion sim --iface` over a veth pair between two network namespaces, RUNS runs of
# SECONDS each without injected jitter and RUNS with it (the simulator's "stall MS": replies held
# back 3..7 ms and sent bunched, every 250 ms; plus tc netem delay 3ms 2ms normal with 25% reordering
# where the kernel has sch_netem), then one run with a real cut (`cut l_elbow`) whose log gives the
# cycle the counter showed it and the cycle the loss was confirmed in.
# usage: toolchain/veth-false-loss-campaign.sh BINARY [RUNS=20] [SECONDS=10]
#   full form (docs/master.md figures): toolchain/veth-false-loss-campaign.sh build/release/rescue-motion 20 10
set -euo pipefail
bin=$(readlink -f "$1"); runs=${2:-20}; secs=${3:-10}
m=rlcamp-m s=rlcamp-s work=$(mktemp -d)
cleanup() { exec 7>&- 2>/dev/null || true; [[ -n ${sim:-} ]] && kill "$sim" 2>/dev/null; ip netns del $m 2>/dev/null; ip netns del $s 2>/dev/null; rm -rf "$work"; }
trap cleanup EXIT
ip netns add $m; ip netns add $s
ip link add name ecm0 netns $m type veth peer name ecs0 netns $s
ip -n $m link set ecm0 up; ip -n $s link set ecs0 up
mkfifo "$work/in"
ip netns exec $s "$bin" sim --iface ecs0 --through-qdisc < "$work/in" > "$work/sim.log" 2>&1 & sim=$!
exec 7>"$work/in"; sleep 1
netem=no
if ip netns exec $s tc qdisc add dev ecs0 root netem delay 3ms 2ms distribution normal reorder 25% 50% 2>/dev/null; then
  ip netns exec $s tc qdisc del dev ecs0 root; netem=yes
fi
echo "netem: $netem"
one_run() {  # $1 = jitter|quiet, $2 = index
  local state="$work/state-$1-$2" log="$work/run-$1-$2.log"; mkdir -p "$state"
  [[ $1 == jitter && $netem == yes ]] && ip netns exec $s tc qdisc add dev ecs0 root netem delay 3ms 2ms distribution normal reorder 25% 50%
  ip netns exec $m "$bin" run --nic raw:ecm0 --duration "$secs" --state-dir "$state" > "$log" 2>&1 & local run=$!
  if [[ $1 == jitter ]]; then
    local k=0; sleep 1.5
    while kill -0 $run 2>/dev/null; do echo "stall $((3 + k % 5))" >&7; k=$((k + 1)); sleep 0.25; done
  fi
  local rc=0; wait $run || rc=$?
  [[ $1 == jitter && $netem == yes ]] && ip netns exec $s tc qdisc del dev ecs0 root
  local lost; lost=$(grep -c "link lost" "$log" || true)
  local late; late=$(sed -n 's/.*frames late or lost: \([0-9]*\).*/\1/p' "$log")
  echo "$1 run $2: exit $rc, link-lost reports $lost, frames late or lost ${late:-?}"
  [[ $lost == 0 && $rc == 0 ]]
}
fails=0
for mode in quiet jitter; do
  for i in $(seq 1 "$runs"); do one_run $mode "$i" || fails=$((fails + 1)); done
done
echo "runs with a false loss or a non-zero exit: $fails of $((2 * runs))"
# A real cut: the run's log names the cycle of the counter that showed it and of the confirmation.
state="$work/state-cut"; mkdir -p "$state"
ip netns exec $m "$bin" run --nic raw:ecm0 --duration 4 --state-dir "$state" > "$work/cut.log" 2>&1 & run=$!
sleep 2.5; echo "cut l_elbow" >&7; wait $run || true; echo "restore l_elbow" >&7
grep -E "link lost|robot" "$work/cut.log" || true
