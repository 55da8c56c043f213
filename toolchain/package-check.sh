#!/usr/bin/env bash
# The Debian package's CI check (docs/deploy.md; toolchain/check.sh stage `package`):
#   1. builds it: cmake --build --preset motion-pc --target package (release-type, tests off)
#   2. checks its metadata (dpkg-deb -I) and contents (dpkg-deb -c)
#   3. lintian: no error, no warning (the info tags left are justified in docs/deploy.md)
#   4. installs it with dpkg -i into a throw-away root: overlays of this machine's /etc, /usr, /var in
#      which a root run of the built program first left its files in /var/lib/rescue-motion (postinst
#      must hand them to the service user);
#      a private mount namespace (CI is root without a booted systemd; this machine never changes), so
#      postinst really runs (service user, state directory, key 0600); runs the installed binary AS
#      THE SERVICE USER with only CAP_NET_RAW, CAP_SYS_NICE, CAP_IPC_LOCK (setpriv) against the
#      in-process simulated robot: `run --check` (OP and back), then the packaged configuration with
#      the link-cut scenario, which must reach OP and leave the error-joints file in the state directory
#      and `bench fig4` of the installed program, run from /, finds /usr/share/rescue-motion/plot_fig4.py
#   5. the unit: systemd-analyze verify, and systemd-analyze security --offline=true (exposure score)
#   6. dpkg --purge: the state directory, the key and the user go
# Usage: toolchain/package-check.sh [JOBS]
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${1:-2}
build=build/motion-pc
fail() { echo "package-check: FAILED: $*" >&2; exit 1; }
step() { printf -- '-- %s\n' "$*"; }

step "build: cmake --build --preset motion-pc --target package"
cmake --preset motion-pc >/dev/null
rm -f "$build"/rescue-motion_*.deb
cmake --build --preset motion-pc -j "$jobs" --target package >"$build/package-build.log" 2>&1 ||
  { tail -n 30 "$build/package-build.log"; fail "package build (log: $build/package-build.log)"; }
deb=$(ls "$build"/rescue-motion_*.deb)
[ "$(echo "$deb" | wc -l)" -eq 1 ] || fail "expected one package, found: $deb"
echo "package: $deb, $(stat -c %s "$deb") bytes"

step "metadata: dpkg-deb -I"
info=$(dpkg-deb -I "$deb")
field() { dpkg-deb -f "$deb" "$1"; }
[ "$(field Package)" = rescue-motion ] || fail "Package field"
[ "$(field Architecture)" = "$(dpkg --print-architecture)" ] || fail "Architecture field"
version=$(field Version)
[[ "$version" =~ ^[0-9][0-9A-Za-z.+~]*$ ]] || fail "Version '$version' is not a Debian version"
# From git describe: it names HEAD's hash (a tagged build: X.Y.Z+N.gHASH). Outside a git checkout the
# project's version alone.
git_hash=$(git rev-parse --short=10 HEAD 2>/dev/null || true)
if [ -n "$git_hash" ]; then
  [[ "$version" == *"$git_hash"* ]] || [[ "$version" == *"+"*".g"* ]] || fail "Version '$version' does not name HEAD ($git_hash)"
fi
depends=$(field Depends)
for d in adduser libc6 libsodium23 libstdc++6; do
  [[ "$depends" == *"$d"* ]] || fail "Depends lacks $d (dpkg-shlibdeps): $depends"
done
for f in conffiles postinst prerm postrm; do echo "$info" | grep -q " $f " || fail "control archive lacks $f"; done
dpkg-deb --ctrl-tarfile "$deb" | tar -xO ./conffiles | grep -qx /etc/rescue-motion/rescue-motion.conf ||
  fail "the default configuration is not a conffile"
echo "Version $version; Depends: $depends"

step "contents: dpkg-deb -c"
contents=$(dpkg-deb -c "$deb")
for path in ./usr/bin/rescue-motion ./lib/systemd/system/rescue-motion.service ./etc/rescue-motion/rescue-motion.conf \
    ./usr/share/man/man1/rescue-motion.1.gz ./usr/share/doc/rescue-motion/copyright \
    ./usr/share/doc/rescue-motion/changelog.gz ./usr/share/doc/rescue-motion/deploy.md \
    ./usr/share/doc/rescue-motion/configuration.md; do
  echo "$contents" | grep -q " $path\$" || fail "package lacks $path"
done
# Every docs page: the program's help and the man page name them (docs/NAME.md).
for page in docs/*.md; do
  echo "$contents" | grep -q " ./usr/share/doc/rescue-motion/$(basename "$page")\$" || fail "package lacks the page $page"
done
man_text=$(dpkg-deb --fsys-tarfile "$deb" | tar -xO ./usr/share/man/man1/rescue-motion.1.gz | gzip -dc)
for section in "EXIT STATUS" "EXAMPLES"; do
  echo "$man_text" | grep -qE "^\.SH \"?$section\"?\$" || fail "the man page has no $section section"
done
echo "$contents" | grep -q "operator.key" && fail "the package ships a key (it must be made at install)"
echo "$contents" | grep " ./usr/bin/rescue-motion$" | grep -q "^-rwxr-xr-x root/root" || fail "binary mode/owner"
echo "$(echo "$contents" | grep -vc '/$') files, all present"

step "lintian"
lint=$(lintian --pedantic --display-info "$deb" 2>&1 | grep -v "running with root privileges" || true)
echo "${lint:-lintian: no tags}"
if echo "$lint" | grep -qE '^(E|W):'; then fail "lintian errors or warnings (see above)"; fi
# Info and pedantic tags left are each justified in docs/deploy.md ("lintian").
allowed='binary-has-unneeded-section|package-supports-alternative-init-but-no-init.d-script'
unjustified=$(echo "$lint" | grep -E '^(I|P):' | grep -vE "$allowed" || true)
[ -z "$unjustified" ] || fail "lintian tags not justified in docs/deploy.md: $unjustified"
echo "lintian verdict: no errors, no warnings; $(echo "$lint" | grep -cE '^(I|P):' || true) info/pedantic tag(s), justified"

step "install with dpkg -i into a throw-away root (overlays of this machine in a private mount namespace)"
# The namespace sees /etc, /usr and /var as overlays whose upper layers are in a temporary directory:
# dpkg -i runs for real there (dependencies checked against this machine's dpkg database, files
# unpacked, the conffile registered, postinst run: adduser, the state directory, the key), and every
# write lands in the temporary layers; this machine's own files never change. /run is an empty tmpfs
# (no booted systemd). shadow and gshadow start empty in the upper layer, so no password hash of this
# machine is ever copied. CI is root: unshare and overlayfs need CAP_SYS_ADMIN.
root=$(mktemp -d /tmp/rescue-motion-root.XXXXXX)
trap 'rm -rf "$root"' EXIT
for d in etc usr var; do mkdir -p "$root/up/$d" "$root/work/$d"; done
: >"$root/up/etc/shadow"; : >"$root/up/etc/gshadow"
chmod 0640 "$root/up/etc/shadow" "$root/up/etc/gshadow"; chgrp shadow "$root/up/etc/shadow" "$root/up/etc/gshadow"
cp "$deb" "$root/rescue-motion.deb"
cp "$build/rescue-motion" "$root/rescue-motion-built"
port=$((20000 + RANDOM % 20000))  # free UDP ports on loopback (other runs may share this machine)
cat >"$root/inside.sh" <<'INSIDE'
set -euo pipefail
root=$1 port=$2
for d in etc usr var; do
  mount -t overlay overlay -o "lowerdir=/$d,upperdir=$root/up/$d,workdir=$root/work/$d" "/$d"
done
mount -t tmpfs tmpfs /run
fail() { echo "package-check: FAILED: $*" >&2; exit 1; }

# A machine where the program once ran as root on the system state directory (a hand run, an older
# package): its lock and error-joints file stay behind, root's. The service user must get them.
echo "a root run of the built program on /var/lib/rescue-motion first (its files stay, root's):"
"$root/rescue-motion-built" run --state-dir /var/lib/rescue-motion --scenario link-cut >"$root/root-run.log" 2>&1 ||
  { tail -n 20 "$root/root-run.log"; fail "the root run"; }
left=$(find /var/lib/rescue-motion -mindepth 1 -user root | wc -l)
[ "$left" -gt 0 ] || fail "the root run left no file to take over"
echo "  $left file(s) owned by root: $(find /var/lib/rescue-motion -mindepth 1 -user root -printf '%f ')"

echo "dpkg -i:"
dpkg -i "$root/rescue-motion.deb" 2>&1 | sed 's/^/  /'
not_taken=$(find /var/lib/rescue-motion ! -user rescue-motion -printf '%p ')
[ -z "$not_taken" ] || fail "postinst left files the service user does not own: $not_taken"
echo "  postinst: every file in /var/lib/rescue-motion is the service user's now"
dpkg-query -W -f='  installed: ${Package} ${Version} ${db:Status-Abbrev}\n' rescue-motion
dpkg-query -W -f='${Conffiles}\n' rescue-motion | grep -q /etc/rescue-motion/rescue-motion.conf || fail "conffile not registered"
id rescue-motion >/dev/null || fail "postinst made no service user"
user_line=$(getent passwd rescue-motion)
echo "  service user: $user_line"
[[ "$user_line" == *":/var/lib/rescue-motion:/usr/sbin/nologin" ]] || fail "service user's home or shell"
[ "$(stat -c '%U %a' /var/lib/rescue-motion)" = "rescue-motion 750" ] || fail "state directory owner/mode: $(stat -c '%U %a' /var/lib/rescue-motion)"
[ "$(stat -c '%U %a' /etc/rescue-motion/operator.key)" = "rescue-motion 600" ] || fail "key owner/mode"
echo "  state directory $(stat -c '%U:%G %a' /var/lib/rescue-motion), key $(stat -c '%U:%G %a' /etc/rescue-motion/operator.key)"

# The service's privileges: its user, no other group, exactly the unit's three ambient capabilities.
as_service() {
  setpriv --reuid=rescue-motion --regid=rescue-motion --clear-groups --no-new-privs \
    --inh-caps=-all,+net_raw,+sys_nice,+ipc_lock --ambient-caps=-all,+net_raw,+sys_nice,+ipc_lock \
    --bounding-set=-all,+net_raw,+sys_nice,+ipc_lock "$@"
}
echo "installed binary as the service user: run --check"
check=$(as_service rescue-motion run --config /etc/rescue-motion/rescue-motion.conf --check) || fail "run --check: $check"
echo "  $check"
echo "installed binary as the service user: the packaged configuration, run --scenario link-cut"
out=$(as_service /usr/bin/rescue-motion run --config /etc/rescue-motion/rescue-motion.conf --listen 127.0.0.1 \
        --control-port "$port" --sensor-port "$((port + 1))" --scenario link-cut 2>&1) || { echo "$out"; fail "the run"; }
echo "$out" | grep -E "privileges:|state directory|operator control port|network in OP|scenario link-cut passed" | sed 's/^/  /'
echo "$out" | grep -q "network in OP" || fail "the installed binary did not reach OP"
echo "$out" | grep -q "privileges: not root; CAP_NET_RAW held, CAP_SYS_NICE held, CAP_IPC_LOCK held" ||
  fail "the service user's privileges are not what the unit grants"
echo "$out" | grep -q "state directory /var/lib/rescue-motion" || fail "not the packaged state directory"
echo "$out" | grep -q "restored lost joints l_elbow,l_wrist_yaw,l_wrist_pitch,l_hand" ||
  fail "the service did not read the error-joints file the root run left"
file=/var/lib/rescue-motion/error-joints.bin
[ -s "$file" ] || fail "no error-joints file in the packaged state directory"
[ "$(stat -c %U "$file")" = rescue-motion ] || fail "error-joints file not owned by the service user"
echo "  error-joints file: $file ($(stat -c '%s bytes, %U:%G %a' "$file"))"

echo "installed binary: bench fig4 from / finds its plot script beside the program"
if /usr/bin/python3 -c 'import matplotlib' 2>/dev/null; then
  (cd / && /usr/bin/rescue-motion bench fig4 --periods 10 --load none --out "$root/fig4" >"$root/fig4.log" 2>&1) ||
    { tail -n 5 "$root/fig4.log"; fail "bench fig4 of the installed program"; }
  [ -s "$root/fig4/fig4.png" ] || fail "bench fig4 of the installed program wrote no PNG"
  echo "  $root/fig4/fig4.png: $(stat -c %s "$root/fig4/fig4.png") bytes (plot script /usr/share/rescue-motion/plot_fig4.py)"
else
  echo "  skipped: /usr/bin/python3 cannot import matplotlib here"
fi

echo "the unit: systemd-analyze verify and security --offline=true"
unit=/lib/systemd/system/rescue-motion.service
systemd-analyze verify --man=no "$unit" || fail "systemd-analyze verify"
echo "  systemd-analyze verify $unit: clean"
security=$(systemd-analyze security --offline=true --no-pager "$unit" 2>&1) || { echo "$security"; fail "systemd-analyze security"; }
score=$(echo "$security" | grep -o "Overall exposure level for rescue-motion.service: [0-9.]* [A-Z]*")
echo "  $score"
awk -v s="$(echo "$score" | awk '{print $(NF-1)}')" 'BEGIN { exit !(s <= 3.0) }' || fail "exposure above 3.0: $score"
grep -E '^(AmbientCapabilities|CapabilityBoundingSet|LimitRTPRIO|LimitMEMLOCK|CPUAffinity|Restart|ProtectSystem|ReadWritePaths|NoNewPrivileges)=' "$unit" | sed 's/^/  /'

echo "dpkg --purge:"
dpkg --purge rescue-motion 2>&1 | sed 's/^/  /'
[ ! -e /var/lib/rescue-motion ] && [ ! -e /etc/rescue-motion/operator.key ] && ! getent passwd rescue-motion >/dev/null ||
  fail "purge left the state directory, the key or the user"
echo "  purged: state directory, key and service user gone"
INSIDE
machine() { getent passwd rescue-motion || true; ls -ld /usr/bin/rescue-motion /var/lib/rescue-motion 2>/dev/null || true
            dpkg-query -W rescue-motion 2>/dev/null || true; md5sum /etc/passwd /etc/group /var/lib/dpkg/status; }
before=$(machine)
unshare --mount --propagation private bash "$root/inside.sh" "$root" "$port"
[ "$(machine)" = "$before" ] || fail "this machine changed (user, files or dpkg database)"
echo "this machine: unchanged (passwd, group, dpkg database, /usr/bin, /var/lib)"
echo "package-check: passed"
