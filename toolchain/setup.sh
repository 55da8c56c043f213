#!/usr/bin/env bash
# Installs every Debian package the project needs. Idempotent: installs only what is missing and
# says what it installs. Run as root (or with sudo available) on Debian 12.
set -euo pipefail

packages=(
  build-essential cmake ninja-build git pkg-config   # build
  g++ clang lld libclang-rt-dev                      # compilers, sanitizer + libFuzzer runtimes
  g++-aarch64-linux-gnu                              # aarch64 cross toolchain
  libeigen3-dev                                      # fixed-size linear algebra (RC tasks)
  libgtest-dev libgmock-dev libbenchmark-dev         # tests and benchmarks
  clang-tidy clang-format cppcheck                   # static analysis
  tshark                                             # Wireshark's dissector: checks our captures
  iproute2                                           # ip netns / veth for raw-socket tests
  graphviz                                           # state-machine diagrams in docs/
  python3 python3-matplotlib                         # plots (Fig. 4 experiment, docs/kinematics.md joint frames)
  python3-jsonschema                                 # ctl --json answers validated against docs/ctl-answer.schema.json
  python3-scipy                                      # toolchain/wcet/pwcet.py: EVT fit and i.i.d. tests (pWCET)
  stress-ng                                          # bench fig4: CPU and memory load on the basic software CPU
  liburdfdom-tools                                   # check_urdf: the robot description is valid URDF
  liborocos-kdl-dev                                  # Orocos KDL: kinematics oracle in tests and bench rc (never firmware)
  libkdl-parser-dev liburdfdom-dev                   # the oracle's KDL trees and inertials read from the URDF file (tests only)
  libfcl-dev                                         # FCL: self-collision of the rescue motion in the URDF's collision geometry (tests only)
  binutils                                           # readelf: vtables for toolchain/rt_verify.py
  rt-tests                                           # cyclictest: the OS latency floor (bench latency)
  valgrind                                           # callgrind: instructions per period (toolchain/instructions.sh)
  libsodium-dev                                      # UDP protocol authentication (crypto_auth), keys
  dpkg-dev fakeroot lintian help2man                 # the Debian package: dpkg-shlibdeps, man page, lintian (docs/deploy.md)
  systemd util-linux                                 # systemd-analyze verify/security on the unit; setpriv (package check)
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ "${#missing[@]}" -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "setup: installing ${#missing[@]} packages: ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
# tshark asks whether non-root users may capture; answer no without a prompt.
echo "wireshark-common wireshark-common/install-setuid boolean false" | $SUDO debconf-set-selections
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "setup: done"
