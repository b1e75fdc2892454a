#!/usr/bin/env bash
# Builds cellform (installing packages as needed) and runs the whole test suite through ctest.
# usage: scripts/test.sh [ctest options...]   e.g. scripts/test.sh -R cells_tests
# (python3-matplotlib too, so that the test of scripts/preview.py runs; a filter that matches no test fails)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh" python3-matplotlib
cd "$root/build"
exec ctest --output-on-failure --no-tests=error -j "${CELLFORM_JOBS:-$(nproc)}" "$@"
