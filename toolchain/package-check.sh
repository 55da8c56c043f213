#!/usr/bin/env bash
# The Debian package's CI check (docs/deploy.md; toolchain/check.sh stage `package`):
#   1. builds it: cmake --build --preset motion-pc --target package (release-type, tests off)
#   2. checks its metadata (dpkg-deb -I) and contents (dpkg-deb -c)
#   3. lintian: no error, no warning (the info tags left are justified in docs/deploy.md)
#   4. installs it into a throw-away root (dpkg-deb -x: CI is root without a booted systemd), does
#      there what postinst does (service user, state directory, key 0600), and runs the installed
#      binary AS THE SERVICE USER with only CAP_NET_RAW, CAP_SYS_NICE, CAP_IPC_LOCK (setpriv) against
#      the in-process simulated robot: `run --check` (OP and back), then a run with the link-cut
#      scenario that must reach OP and leave the error-joints file in the packaged state directory
#   5. the unit: systemd-analyze verify, and systemd-analyze security --offline=true (exposure score)
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

step "install into a throw-away root"
root=$(mktemp -d /tmp/rescue-motion-root.XXXXXX)
trap 'rm -rf "$root"' EXIT
dpkg-deb -x "$deb" "$root"
chmod 0755 "$root"
# What postinst does on the robot (adduser --system, install -d, keygen, chmod 0600), in the root:
# a numeric service uid that exists nowhere on this machine, written into the root's own passwd.
uid=61874
while getent passwd "$uid" >/dev/null || getent group "$uid" >/dev/null; do uid=$((uid + 1)); done
mkdir -p "$root/etc"
echo "rescue-motion:x:$uid:$uid:rescue-motion firmware service:/var/lib/rescue-motion:/usr/sbin/nologin" >"$root/etc/passwd"
echo "rescue-motion:x:$uid:" >"$root/etc/group"
install -d -o "$uid" -g "$uid" -m 0750 "$root/var/lib/rescue-motion"
"$root/usr/bin/rescue-motion" ctl keygen --key "$root/etc/rescue-motion/operator.key" >/dev/null
chown "$uid:$uid" "$root/etc/rescue-motion/operator.key"
chmod 0600 "$root/etc/rescue-motion/operator.key"
echo "root $root; service user rescue-motion = uid $uid; key $(stat -c '%a %u' "$root/etc/rescue-motion/operator.key")"

# The service's privileges: its uid, no groups, exactly the unit's three ambient capabilities.
as_service() {
  setpriv --reuid="$uid" --regid="$uid" --clear-groups --no-new-privs \
    --inh-caps=-all,+net_raw,+sys_nice,+ipc_lock --ambient-caps=-all,+net_raw,+sys_nice,+ipc_lock \
    --bounding-set=-all,+net_raw,+sys_nice,+ipc_lock "$@"
}
# The packaged configuration, with the paths of the throw-away root given on the command line (which
# overrides the file) and free UDP ports on loopback (other runs may share this machine).
port=$((20000 + RANDOM % 20000))
run_args=(--config "$root/etc/rescue-motion/rescue-motion.conf" --state-dir "$root/var/lib/rescue-motion"
          --key "$root/etc/rescue-motion/operator.key" --listen 127.0.0.1 --control-port "$port" --sensor-port "$((port + 1))")

step "installed binary as the service user: run --check"
check=$(as_service "$root/usr/bin/rescue-motion" run --config "$root/etc/rescue-motion/rescue-motion.conf" --check) ||
  fail "run --check: $check"
echo "$check"

step "installed binary as the service user: run --scenario link-cut"
out=$(as_service "$root/usr/bin/rescue-motion" run "${run_args[@]}" --scenario link-cut 2>&1) || {
  echo "$out"
  fail "the run as the service user"
}
echo "$out" | grep -E "privileges:|network in OP|scenario link-cut passed|heap allocations" || true
echo "$out" | grep -q "network in OP" || fail "the installed binary did not reach OP"
echo "$out" | grep -q "privileges: not root; CAP_NET_RAW held, CAP_SYS_NICE held, CAP_IPC_LOCK held" ||
  fail "the service user's privileges are not what the unit grants"
file="$root/var/lib/rescue-motion/error-joints.bin"
[ -s "$file" ] || fail "no error-joints file in the packaged state directory"
[ "$(stat -c %u "$file")" = "$uid" ] || fail "error-joints file not owned by the service user"
echo "error-joints file: $file ($(stat -c '%s bytes, mode %a, uid %u' "$file"))"

step "the unit: systemd-analyze verify and security --offline=true"
unit=$root/lib/systemd/system/rescue-motion.service
# verify resolves ExecStart= on this machine: a copy that runs the root's binary.
mkdir -p "$root/verify"
sed "s#/usr/bin/rescue-motion#$root/usr/bin/rescue-motion#" "$unit" >"$root/verify/rescue-motion.service"
systemd-analyze verify --man=no "$root/verify/rescue-motion.service" || fail "systemd-analyze verify"
echo "systemd-analyze verify: clean"
security=$(systemd-analyze security --offline=true --no-pager --root="$root" rescue-motion.service 2>&1) ||
  { echo "$security"; fail "systemd-analyze security"; }
score=$(echo "$security" | grep -o "Overall exposure level for rescue-motion.service: [0-9.]* [A-Z]*")
echo "$score"
awk -v s="$(echo "$score" | awk '{print $(NF-1)}')" 'BEGIN { exit !(s <= 3.0) }' || fail "exposure above 3.0: $score"
grep -E '^(AmbientCapabilities|CapabilityBoundingSet|LimitRTPRIO|LimitMEMLOCK|CPUAffinity|Restart|ProtectSystem|ReadWritePaths|NoNewPrivileges)=' "$unit"
echo "package-check: passed"
