#!/usr/bin/env bash
# Sets up, builds (release preset) and runs the firmware; arguments go to `rescue-motion run`.
# With no arguments it drives the simulated robot until Ctrl-C.
set -euo pipefail
cd "$(dirname "$0")/.."
bash toolchain/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)"
exec ./build/release/rescue-motion run "$@"
