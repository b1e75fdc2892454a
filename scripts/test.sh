#!/usr/bin/env bash
# Builds cellform (installing packages as needed) and runs the whole test suite through ctest.
# usage: scripts/test.sh [ctest options...]   e.g. scripts/test.sh -R cells_tests
# (python3-matplotlib too, if it can be, so that the test of scripts/preview.py runs; a filter that matches no
# test fails)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh"
# matplotlib only for the test of scripts/preview.py, which is skipped without it
"$root/scripts/setup.sh" python3-matplotlib ||
  echo "cellform: python3-matplotlib could not be installed: the test of scripts/preview.py is skipped" >&2
cd "$root/build"
exec ctest --output-on-failure --no-tests=error -j "${CELLFORM_JOBS:-$(nproc)}" "$@"
