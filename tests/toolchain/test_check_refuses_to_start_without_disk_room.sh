#!/usr/bin/env bash
# toolchain/check.sh refuses to start a building stage when the disk cannot hold its largest build
# (issue 35 item 18: a run otherwise fails late, in a link of the asan tests): with `df` reporting
# 100 MB free it exits 1 naming the figures before running anything (here the `cross` stage, whose
# `cmake` is replaced by one that says it ran). With enough room it starts the stage.
# Usage: test_check_refuses_to_start_without_disk_room.sh SOURCE_DIR
set -euo pipefail
source_dir=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/tree/toolchain" "$tmp/bin"
cp "$source_dir/toolchain/check.sh" "$tmp/tree/toolchain/"
fake_df() {  # fake_df MB: a df that reports MB available (POSIX -P -m layout), whatever it is asked
  cat > "$tmp/bin/df" <<DF
#!/bin/sh
echo "Filesystem 1048576-blocks Used Available Capacity Mounted on"
echo "/dev/fake 9999 9999 $1 99% /"
DF
  chmod +x "$tmp/bin/df"
}
printf '#!/bin/sh\necho "cmake ran" >&2; exit 3\n' > "$tmp/bin/cmake"
chmod +x "$tmp/bin/cmake"

fake_df 100
status=0
out=$(PATH="$tmp/bin:$PATH" RESCUE_PRUNE_BUILDS=1 bash "$tmp/tree/toolchain/check.sh" cross 2>&1) || status=$?
echo "$out"
[ "$status" = 1 ] || { echo "FAIL: exit $status, expected 1"; exit 1; }
grep -q "not enough disk: 100 MB free + 0 MB in build/ < 2048 MB needed" <<<"$out" || { echo "FAIL: no figures"; exit 1; }
if grep -q "cmake ran" <<<"$out"; then echo "FAIL: a stage started"; exit 1; fi

fake_df 3000
status=0
out=$(PATH="$tmp/bin:$PATH" RESCUE_PRUNE_BUILDS=1 bash "$tmp/tree/toolchain/check.sh" cross 2>&1) || status=$?
grep -q "cmake ran" <<<"$out" || { echo "FAIL: with room the stage did not start: $out"; exit 1; }
echo "PASS"
