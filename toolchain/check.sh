#!/usr/bin/env bash
# The project's test command (README, .ci/run): sets up, builds and passes every check.
#   1. install the Debian packages (toolchain/setup.sh)
#   1b. README command 1 as a new user runs it: toolchain/run.sh --duration 3 (release build of the
#      program, 3 s on the simulated robot), so the first command of the README can never break silently
#   1c. load: the end-to-end real-time tests (label `serial`: a real `rescue-motion run` on the wall
#      clock) and the tests labelled `plain` (what a sanitizer build cannot prove: the heap guard's cover
#      of malloc, SCHED_FIFO, ulimit -v) on the release build (the optimised program), while stress-ng
#      loads every CPU at normal priority; stress-ng is started and always stopped here
#   2. test: AddressSanitizer + UndefinedBehaviorSanitizer build (a Debug build: assertions on) + the
#      GoogleTest suite through CTest, the `serial` ones too (their timing is proven in stage load). One build proves
#      the logic and the memory: a separate plain debug build and run of the same suite cost CI about
#      9 minutes and proved nothing more than this one and the `plain` tests above (docs/build.md)
#   3. static analysis: clang-tidy + cppcheck over the firmware (fails on any finding)
#   3b. verify: release-flag build with GCC's stack usage and call graph + toolchain/rt_verify.py
#      (deepest stack of each real-time period function, no allocation/lock/blocking call on it)
#   4. ThreadSanitizer build + the tests labelled 'concurrency'
#   6. fuzz build (clang, every library instrumented) + a short bounded run of each fuzzer
#   7. aarch64 cross compile of the firmware libraries
#   8. package: the Debian package (motion-pc preset), its contents, lintian, the installed binary as the
#      service user on the simulated robot, the systemd unit (toolchain/package-check.sh, docs/deploy.md)
# Stages can be chosen: toolchain/check.sh [setup] [run] [load] [test] [analysis] [verify] [tsan] [fuzz] [cross] [package]
# (`asan` is another name for `test`). A developer's plain debug build: cmake --preset debug (docs/build.md).
# Disk: every build with -g compresses its debug info (-gz, CMakePresets.json). After each stage the
# script prints the free space and the size of every build directory ("disk: ..." lines). With
# RESCUE_PRUNE_BUILDS=1 (.ci/run sets it) each build directory but release's is removed after the last
# stage that uses it, so a run needs room for its largest build (asan, about 1.8 GB), not for all of
# them at once (5 GB uncompressed: a CI machine once ran out of disk linking the asan tests).
set -euo pipefail
cd "$(dirname "$0")/.."
stages=("$@")
[ "${#stages[@]}" -gt 0 ] || stages=(setup run load test analysis verify tsan fuzz cross package)
jobs=$(nproc)
fuzz_seconds=${RESCUE_FUZZ_SECONDS:-10}  # the short CI form; a full run: RESCUE_FUZZ_SECONDS=600 bash toolchain/check.sh fuzz

want() { local s; for s in "${stages[@]}"; do [ "$s" = "$1" ] && return 0; [ "$s" = asan ] && [ "$1" = test ] && return 0; done; return 1; }
# Each banner also says how long the stage before it took, so a slow stage is seen in CI's log.
stage_start=$(date +%s)
banner() {
  local now; now=$(date +%s)
  printf '\n(%s s)\n==== %s ====\n' "$(( now - stage_start ))" "$*"
  stage_start=$now
}
disk_report() {  # free space where the builds go, and what each build directory takes
  local builds
  builds=$({ du -sh build/*/ 2>/dev/null || true; } | awk '{sub("/$", "", $2); printf " %s %s", $2, $1}')
  echo "disk: $1: $({ df -h --output=avail . 2>/dev/null || echo ?; } | tail -n 1 | tr -d ' ') free;${builds:- no build directory}"
}
finished_with() {  # finished_with STAGE BUILD_DIR: the stage was the build's last user
  if [ "${RESCUE_PRUNE_BUILDS:-0}" = 1 ]; then rm -rf "build/$2"; fi
  disk_report "after $1"
}
disk_report "start"
# Room for the largest build first (asan, about 1.8 GB, plus release's: ~2 GB at the peak with
# RESCUE_PRUNE_BUILDS=1; every build kept: ~5.3 GB): a full disk otherwise ends the run late, far from
# its cause, in a link of the asan tests. Build directories already there count as room (rebuilt in
# place or pruned). RESCUE_MIN_FREE_MB overrides the figure (0: no check).
build_stages=(load test analysis verify tsan asan fuzz cross package)
needs_room=0
for s in "${build_stages[@]}"; do want "$s" && needs_room=1; done
if [ "$needs_room" = 1 ]; then
  if [ "${RESCUE_PRUNE_BUILDS:-0}" = 1 ]; then default_room_mb=2048; else default_room_mb=5300; fi
  need_mb=${RESCUE_MIN_FREE_MB:-$default_room_mb}
  free_mb=$(df -Pm . | awk 'NR == 2 { print $4 }')
  held_mb=$({ du -sm build 2>/dev/null || echo 0; } | awk '{ print $1 }')
  if [ -n "$free_mb" ] && [ "$(( free_mb + held_mb ))" -lt "$need_mb" ]; then
    echo "check.sh: not enough disk: ${free_mb} MB free + ${held_mb} MB in build/ < ${need_mb} MB needed at the peak" \
         "(RESCUE_PRUNE_BUILDS=${RESCUE_PRUNE_BUILDS:-0}; docs/build.md \"Disk\"): free some space, or RESCUE_MIN_FREE_MB=N" >&2
    exit 1
  fi
fi
start=$(date +%s)

if want setup; then banner "setup"; bash toolchain/setup.sh; fi

if want run; then
  banner "README command 1: toolchain/run.sh --duration 3"
  bash toolchain/run.sh --duration 3
fi

if want load; then
  banner "load: end-to-end real-time tests (serial) and the plain ones on the release build, every CPU loaded by stress-ng"
  cmake --preset release >/dev/null
  # The program, the serial tests and the plain ones only (targets `serial_tests`, `plain_tests`): the
  # rest of the suite proves logic and runs in the test stage.
  cmake --build --preset release -j "$jobs" --target rescue-motion serial_tests plain_tests
  # Every CPU busy at normal priority (SCHED_OTHER, nice 0) plus a memory hog, in its own process
  # group so that it is always stopped, whatever the tests do; --timeout bounds it should this
  # script be killed before it can stop it.
  setsid stress-ng --cpu 0 --vm 1 --vm-bytes 256M --timeout 30m --quiet &
  stress_pid=$!
  stop_stress() { kill -TERM -- "-$stress_pid" 2>/dev/null || true; wait "$stress_pid" 2>/dev/null || true; }
  trap stop_stress EXIT
  load_start=$(date +%s)
  load_status=0
  ctest --preset release -L serial || load_status=$?
  ctest --preset release -j "$jobs" -L plain -LE serial || load_status=$?
  stop_stress
  trap - EXIT
  echo "load: serial and plain tests under stress-ng finished in $(( $(date +%s) - load_start )) s (status $load_status)"
  [ "$load_status" -eq 0 ]
  disk_report "after load"
fi

if want test; then
  banner "AddressSanitizer + UndefinedBehaviorSanitizer build + every test (the serial ones also ran in stage load, on the release build)"
  cmake --preset asan >/dev/null
  cmake --build --preset asan -j "$jobs"
  ctest --preset asan -j "$jobs"
  finished_with test asan
fi

if want analysis; then
  banner "static analysis"
  # The debug preset's compile commands, and the one header the build generates (the robot's
  # description): nothing else of the debug build is needed to analyse the sources.
  cmake --preset debug >/dev/null
  cmake --build --preset debug --target rescue_robot_description
  bash toolchain/static-analysis.sh . build/debug
  finished_with analysis debug
fi

if want verify; then
  banner "static verification: stack depth and blocking calls of the real-time tasks"
  cmake --preset verify >/dev/null
  cmake --build --preset verify -j "$jobs"
  python3 toolchain/rt_verify.py --build build/verify --source .
  finished_with verify verify
fi

if want tsan; then
  banner "ThreadSanitizer: concurrency tests"
  cmake --preset tsan >/dev/null
  # Only the concurrency tests run under TSan, so only they (and what they link) are built.
  cmake --build --preset tsan -j "$jobs" --target concurrency_tests
  ctest --preset tsan -j "$jobs"
  finished_with tsan tsan
fi

if want fuzz; then
  banner "libFuzzer: ${fuzz_seconds}s per target"
  cmake --preset fuzz >/dev/null
  cmake --build --preset fuzz -j "$jobs"
  # The fuzzers run $jobs at a time (each is single-threaded and gets a CPU of its own for its
  # ${fuzz_seconds} s), each into its own log, printed in order; any fuzzer's failure fails the stage.
  fuzz_one() {  # fuzz_one FUZZER LOG: a bounded run; the exit status is the fuzzer's
    local f=$1 corpus seeds
    corpus="build/fuzz/fuzz/corpus-$(basename "$f")"
    seeds="$(dirname "$f")/seeds-$(basename "$f")"
    mkdir -p "$corpus"
    "$f" -max_total_time="$fuzz_seconds" -artifact_prefix="build/fuzz/fuzz/" -print_final_stats=1 "$corpus" $( [ -d "$seeds" ] && echo "$seeds" ) >"$2" 2>&1
  }
  fuzz_collect() {  # waits for the running fuzzers and prints each one's last lines, in order
    local i
    for i in "${!fuzz_pids[@]}"; do
      wait "${fuzz_pids[$i]}" || { echo "fuzz: ${fuzz_names[$i]} FAILED"; fuzz_failed=1; }
      echo "fuzz: ${fuzz_names[$i]}"; tail -n 12 "${fuzz_names[$i]}.log"
    done
    fuzz_pids=(); fuzz_names=()
  }
  fuzzers=0
  fuzz_failed=0
  fuzz_pids=()
  fuzz_names=()
  for f in build/fuzz/fuzz/fuzz_*; do
    [ -x "$f" ] || continue  # also the unexpanded pattern when there is no fuzzer yet
    fuzzers=$((fuzzers + 1))
    fuzz_one "$f" "$f.log" &
    fuzz_pids+=("$!")
    fuzz_names+=("$f")
    if [ "${#fuzz_pids[@]}" -ge "$jobs" ]; then
      fuzz_collect
    fi
  done
  fuzz_collect
  [ "$fuzz_failed" -eq 0 ]
  [ "$fuzzers" -gt 0 ] || echo "fuzz: no fuzz targets yet (tests/fuzz/fuzzers.cmake lists none)"
  finished_with fuzz fuzz
fi

if want cross; then
  banner "aarch64 cross compile (firmware libraries)"
  cmake --preset aarch64 >/dev/null
  cmake --build --preset aarch64 -j "$jobs"
  finished_with cross aarch64
fi

if want package; then
  banner "Debian package: contents, lintian, installed binary as the service user, systemd unit"
  bash toolchain/package-check.sh "$jobs"
  finished_with package motion-pc
fi

banner "all checks passed in $(( $(date +%s) - start )) s"
