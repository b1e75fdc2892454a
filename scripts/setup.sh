#!/usr/bin/env bash
# Installs the Debian packages cellform needs (only those missing), then configures and builds
# in Release into build/. Run by run.sh and test.sh; safe to run again (quick when up to date).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
packages=(cmake g++ make pkg-config libopenmesh-dev libnanoflann-dev libeigen3-dev libopenvdb-dev
          libboost-iostreams-dev libtbb-dev catch2 liblua5.4-dev nlohmann-json3-dev libcairo2-dev openscad admesh)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "cellform: installing Debian packages: ${missing[*]}" >&2
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends \
    -o DPkg::Lock::Timeout=600 "${missing[@]}" >/dev/null
fi
jobs="${CELLFORM_JOBS:-$(nproc)}"
if [ ! -f "$root/build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$root/build" -j "$jobs" -- --no-print-directory >&2
