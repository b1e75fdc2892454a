#!/usr/bin/env bash
# Installs the Debian packages cellform needs (only those missing), then configures and builds
# in Release into build/. Run by run.sh and test.sh; safe to run again (quick when up to date).
# usage: scripts/setup.sh [more Debian packages...]   (test.sh adds python3-matplotlib, for preview.py)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
packages=(cmake g++ make pkg-config libopenmesh-dev libeigen3-dev libopenvdb-dev libboost-iostreams-dev
          libtbb-dev catch2 liblua5.4-dev nlohmann-json3-dev libcairo2-dev openscad admesh "$@")
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "cellform: installing Debian packages: ${missing[*]}" >&2
  sudo_cmd=()
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || {
      echo "cellform: these packages are missing and sudo is not installed: run this as root once" >&2
      exit 1
    }
    sudo_cmd=(sudo)
  fi
  "${sudo_cmd[@]}" apt-get update -qq
  # (env: sudo resets the environment, and apt would ask its questions where nobody sees them)
  "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    -o DPkg::Lock::Timeout=600 "${missing[@]}" >/dev/null
fi
jobs="${CELLFORM_JOBS:-$(nproc)}"
# configured unless the build files are there: a configure that failed or was stopped leaves CMakeCache.txt
# without them, and make then failed on every later run
if [ ! -f "$root/build/Makefile" ]; then
  cmake -S "$root" -B "$root/build" -G "Unix Makefiles" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$root/build" -j "$jobs" -- --no-print-directory >&2
