#!/usr/bin/env bash
# For the man page's tests: writes OUT_DIR/rescue-motion.1 with packaging/make-man.sh and prints the
# page as man shows it at 80 columns, plain text. Usage: SOURCE_DIR BINARY OUT_DIR
set -euo pipefail
source=$1 binary=$2 out=$3
bash "$source/packaging/make-man.sh" "$binary" 0.0-test "$out/rescue-motion.1"
MANWIDTH=80 MAN_KEEP_FORMATTING= man -l "$out/rescue-motion.1" 2>/dev/null | col -b
