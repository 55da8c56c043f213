#!/usr/bin/env bash
# Rewrites the generated blocks of docs/*.md from the program's own output. A block is
#   <!-- BEGIN GENERATED: rescue-motion ARGS -->
#   ...output of `rescue-motion ARGS` (inside a ```dot fence when ARGS contain --format dot)...
#   <!-- END GENERATED -->
# Usage: toolchain/update-generated-docs.sh [BUILD_DIR]   (default build/debug; the program must be built)
# tests/app/test_docs_fsm_output_equals_committed_docs checks that the blocks are current.
set -euo pipefail
cd "$(dirname "$0")/.."
program="${1:-build/debug}/rescue-motion"
[ -x "$program" ] || { echo "update-generated-docs: $program not built"; exit 1; }
for doc in docs/*.md; do
  python3 - "$program" "$doc" <<'PY'
import re, subprocess, sys
program, path = sys.argv[1], sys.argv[2]
text = open(path).read()
pattern = re.compile(r"(<!-- BEGIN GENERATED: rescue-motion (.*?) -->\n)(.*?)(<!-- END GENERATED -->)", re.S)
def regenerate(m):
    args = m.group(2).split()
    out = subprocess.run([program] + args, check=True, capture_output=True, text=True).stdout
    if "dot" in args:
        out = "```dot\n" + out + "```\n"
    return m.group(1) + out + m.group(4)
new = pattern.sub(regenerate, text)
if new != text:
    open(path, "w").write(new)
    print(f"update-generated-docs: rewrote {path}")
PY
done
