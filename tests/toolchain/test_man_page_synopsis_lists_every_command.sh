#!/usr/bin/env bash
# The man page (packaging/make-man.sh on the built program) has a SYNOPSIS naming each command's
# form as its --help's usage line, and only the sections it means to have (a wrapped help line that
# starts with "[" once became a section of its own). Usage: SOURCE_DIR BINARY
set -euo pipefail
source=$1 binary=$2
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
page=$(bash "$source/tests/toolchain/render_man_page.sh" "$source" "$binary" "$out")
# The SYNOPSIS section's text, its wrapped lines joined, spaces collapsed.
synopsis=$(echo "$page" | awk '/^SYNOPSIS$/ {on = 1; next} /^[A-Z]/ {on = 0} on' | tr -s ' \t\n' ' ')
[ -n "$synopsis" ] || { echo "FAILED: no SYNOPSIS section"; exit 1; }
forms=0
for cmd in $("$binary" --help | awk '/^commands:/ {on = 1; next} on && /^  [a-z]/ {print $1}'); do
  form=$("$binary" "$cmd" --help | sed -n '1s/^usage: //p' | tr -s ' ' ' ')
  case "$synopsis" in
    *" $form "*) forms=$((forms + 1)) ;;
    *) echo "FAILED: SYNOPSIS lacks '$form'"; echo "$synopsis"; exit 1 ;;
  esac
done
[ "$forms" -ge 6 ] || { echo "FAILED: only $forms commands in rescue-motion --help"; exit 1; }
case "$synopsis" in *"rescue-motion --help | --version"*) ;; *) echo "FAILED: SYNOPSIS lacks --help | --version"; exit 1 ;; esac
sections=$(grep '^\.SH' "$out/rescue-motion.1" | sed -e 's/^\.SH //' -e 's/"//g' | tr '\n' ',')
expected="NAME,SYNOPSIS,DESCRIPTION,COMMANDS IN DETAIL,EXIT STATUS,FILES,EXAMPLES,SEE ALSO,"
[ "$sections" = "$expected" ] || { echo "FAILED: sections $sections, expected $expected"; exit 1; }
echo "man page: SYNOPSIS names $forms commands' forms; sections $sections"
