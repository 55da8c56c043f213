#!/usr/bin/env bash
# Writes the man page rescue-motion.1 from the program's own help: help2man (Debian help2man) on
# `rescue-motion --help`, with each command's `--help` as a subsection and the package's files.
# Usage: make-man.sh BINARY VERSION OUTPUT
set -euo pipefail
binary=$1 version=$2 out=$3
include=$(mktemp)
trap 'rm -f "$include"' EXIT
{
  echo "[COMMANDS IN DETAIL]"
  for cmd in run sim ctl decode bench docs; do
    echo ".SS \"rescue-motion $cmd\""
    echo ".nf"
    # roff: a backslash is written \e; a line starting with . or ' is protected by \&.
    "$binary" "$cmd" --help | sed -e 's/\\/\\e/g' -e "s/^\\([.']\\)/\\\\\\&\\1/"
    echo ".fi"
  done
  cat <<'TXT'
[FILES]
.TP
.I /etc/rescue-motion/rescue-motion.conf
the service's configuration (run \-\-config; /usr/share/doc/rescue-motion/configuration.md)
.TP
.I /etc/rescue-motion/operator.key
the operator's pre-shared key, mode 0600, owner rescue-motion
.TP
.I /var/lib/rescue-motion
the state directory: the error-joints file, the instance lock
.TP
.I /lib/systemd/system/rescue-motion.service
the hardened service (/usr/share/doc/rescue-motion/deploy.md)
[SEE ALSO]
.BR systemctl (1),
.BR journalctl (1);
/usr/share/doc/rescue-motion/deploy.md (install, verify, start, roll back, logs, real-time tuning)
TXT
} > "$include"
help2man --no-info --no-discard-stderr --section=1 --version-string="$version" \
  --name="motion-control firmware of the rescue robot (EtherCAT master, joint manager)" \
  --include="$include" --output="$out" "$binary"
