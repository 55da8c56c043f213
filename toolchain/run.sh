#!/usr/bin/env bash
# README command 1: sets up, builds the program (release preset, the `rescue-motion` target only: the
# tests are built by toolchain/check.sh) and runs it; arguments go to `rescue-motion run`.
# With no arguments it drives the simulated robot until Ctrl-C.
# A run from the source tree keeps its state in build/release/state (never the motion PC's system
# directory /var/lib/rescue-motion, which belongs to the installed package); --state-dir, or a
# --config file's state_dir, overrides it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash toolchain/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)" --target rescue-motion
state_dir=()
case " $* " in
  *" --state-dir "*|*" --state-dir="*|*" --config "*|*" --config="*) ;;  # theirs, or the configuration's
  *) state_dir=(--state-dir "$PWD/build/release/state") ;;  # absolute, as --state-dir must be
esac
exec ./build/release/rescue-motion run "${state_dir[@]}" "$@"
