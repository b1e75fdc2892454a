#!/usr/bin/env bash
# Builds cellform (installing packages as needed) and runs a growth script, by default the leaf.
# usage: scripts/run.sh [SCRIPT] [cellform run options...]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh"
script="${1:-$root/examples/leaf.lua}"
[ $# -gt 0 ] && shift
exec "$root/build/bin/cellform" run "$script" "$@"
