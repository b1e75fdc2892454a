#!/usr/bin/env bash
# Builds cellform (installing packages as needed) and runs the whole test suite through ctest.
# usage: scripts/test.sh [ctest options...]   e.g. scripts/test.sh -L fast, scripts/test.sh -R cells
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh"
cd "$root/build"
exec ctest --output-on-failure -j "${CELLFORM_JOBS:-$(nproc)}" "$@"
