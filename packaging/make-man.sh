#!/usr/bin/env bash
# Writes the man page rescue-motion.1 from the program's own help: help2man (Debian help2man) on
# `rescue-motion --help`, with each command's `--help` as a subsection and the package's files.
# Usage: make-man.sh BINARY VERSION OUTPUT
set -euo pipefail
binary=$1 version=$2 out=$3
here=$(cd "$(dirname "$0")" && pwd)
include=$(mktemp)
trap 'rm -f "$include"' EXIT
commands="run sim ctl decode bench docs"
# roff: a backslash is written \e; a line starting with . or ' is protected by \&, and so is one
# starting with [, which help2man would take for a section of this include file.
roff_text() { sed -e 's/\\/\\e/g' -e "s/^\\([.'[]\\)/\\\\\\&\\1/"; }
{
  # Each command's form: the first line of its --help ("usage: rescue-motion run [OPTIONS]").
  echo "[SYNOPSIS]"
  echo ".nh"
  echo ".SY rescue-motion"
  echo "\\-\\-help | \\-\\-version"
  for cmd in $commands; do
    echo ".SY rescue-motion"
    "$binary" "$cmd" --help | sed -n -e "1s/^usage: rescue-motion //p" | roff_text
  done
  echo ".YS"
  echo "[COMMANDS IN DETAIL]"
  for cmd in $commands; do
    echo ".SS \"rescue-motion $cmd\""
    echo ".nf"
    # Wrapped to 72 columns: the man page's blocks are indented, the page stays within 80 columns.
    "$binary" "$cmd" --help | python3 "$here/wrap-help.py" 72 | roff_text
    echo ".fi"
  done
  cat <<'TXT'
[FILES]
.nh
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
[EXIT STATUS]
.nh
.TP
.B 0
run: a clean stop (signal or \-\-duration) and, with \-\-scenario, the scenario passed; run \-\-check: the
network went to OP and back; ctl: the robot accepted the command or answered the query; the other
commands: success.
.TP
.B 1
a failure: a bad option or configuration (with its file and line), the NIC, the bring\-up, a failed
scenario; ctl: refused by the robot or the drive, the reason printed.
.TP
.B 2
a usage error: an unknown command or option, an option without its value; ctl: also a bad or
missing argument, an argument too many, an option of another verb (nothing is sent).
.TP
.B 3
run: the robot ended in error (every joint in Error). ctl: unreachable: no authentic answer within
\-\-timeout (not running, wrong port, or another key), or another robot id than \-\-robot.
.TP
.B 4
run: a critical task died (the EtherCAT handler or the joint manager); the reason is printed. ctl:
local: the key or configuration file cannot be used, so nothing was asked.
.TP
.B 5
run: a reference was sent beyond a joint's speed, acceleration or jerk limit (the joint, the figure and
the limit are printed; joint_limits: exceeded). ctl: an authentic answer that does not fit the request.
.TP
.B 6
run: the shared\-memory segment was found damaged; every task stopped (safe hold), no figures printed.
[EXAMPLES]
.nh
.TP
.B rescue-motion run \-\-state\-dir /tmp/rm \-\-duration 5
the simulated robot for five seconds, its state kept in /tmp/rm.
.TP
.B rescue-motion run \-\-scenario link\-cut \-\-state\-dir /tmp/rm
the cable into l_elbow cut one second after OP; exit 0 when exactly the joints behind it were marked lost.
.TP
.B sudo rescue-motion run \-\-config /etc/rescue-motion/rescue-motion.conf \-\-check
verify the robot's network before starting the service (OP and back, no drive enabled).
.TP
.B sudo rescue-motion ctl status
the 21 joints of the running service (ctl reads key_file and control_port from the configuration).
.TP
.B rescue-motion ctl \-\-host 10.0.0.2 \-\-key ~/robot.key \-\-json status
the same from an operator station, as one JSON object.
.TP
.B rescue-motion ctl enable l_elbow,l_hand
enable two joints, or none: a refused command names every blocking joint and changes nothing.
.TP
.B rescue-motion decode capture.pcapng
one line per EtherCAT datagram of a capture.
[SEE ALSO]
.BR systemctl (1),
.BR journalctl (1);
/usr/share/doc/rescue-motion/deploy.md (install, verify, start, roll back, logs, real-time tuning).
A page named docs/NAME.md in this manual is installed as /usr/share/doc/rescue-motion/NAME.md.
TXT
} > "$include"
help2man --no-info --no-discard-stderr --section=1 --version-string="$version" \
  --name="motion-control firmware of the rescue robot (EtherCAT master, joint manager)" \
  --include="$include" --output="$out" "$binary"
