#!/usr/bin/env bash
# The man page (packaging/make-man.sh on the built program) rendered at 80 columns: no line longer,
# EXIT STATUS and EXAMPLES present, and every docs page it names (docs/NAME.md, or
# /usr/share/doc/rescue-motion/NAME.md) exists in docs/, all of which the package installs
# (packaging/CMakeLists.txt). Usage: SOURCE_DIR BINARY
set -euo pipefail
source=$1 binary=$2
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
page=$(bash "$source/tests/toolchain/render_man_page.sh" "$source" "$binary" "$out")
long=$(echo "$page" | awk 'length > 80' | head -5)
[ -z "$long" ] || { echo "FAILED: lines over 80 columns:"; echo "$long"; exit 1; }
for section in "EXIT STATUS" "EXAMPLES" "FILES" "SEE ALSO"; do
  echo "$page" | grep -q "^$section\$" || { echo "FAILED: no $section section"; exit 1; }
done
for name in $(grep -oE '(docs|/usr/share/doc/rescue-motion)/[A-Za-z0-9_-]+\.md' "$out/rescue-motion.1" | sed 's|.*/||' | sort -u); do
  [ -f "$source/docs/$name" ] || [ "$name" = README.md ] || [ "$name" = NAME.md ] || { echo "FAILED: the page names $name, which docs/ lacks"; exit 1; }
done
grep -q 'file(GLOB rescue_doc_pages ${PROJECT_SOURCE_DIR}/docs/\*.md)' "$source/packaging/CMakeLists.txt" ||
  { echo "FAILED: the package does not install every docs page"; exit 1; }
echo "man page: $(echo "$page" | wc -l) lines within 80 columns; EXIT STATUS, EXAMPLES; every named page installed"
