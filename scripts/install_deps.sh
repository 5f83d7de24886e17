#!/usr/bin/env bash
# Installs the Debian packages slamcmp needs, only those that are missing.
# Runs as root on CI; uses sudo for a user.
set -euo pipefail
packages=(build-essential cmake pkg-config
          libopencv-dev libopencv-contrib-dev libeigen3-dev
          libcli11-dev nlohmann-json3-dev libfmt-dev libyaml-dev
          libgtest-dev libgmock-dev libbenchmark-dev gnuplot-nox
          parallel)  # GNU parallel: `parallel < jobs.txt` of compare --plan, and its test
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
echo "installing: ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
