#!/usr/bin/env bash
# Regenerates the parameter reference at the end of docs/scripting.md from `cellform params`
# (the test suite checks that the page matches the program).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
doc="$root/docs/scripting.md"
marker="These tables are printed by \`cellform params\`; the test suite checks that this page matches it."
head_part="$(sed "/^$(printf '%s' "$marker" | sed 's/[][\.*^$/]/\\&/g')\$/q" "$doc")"
{ printf '%s\n' "$head_part"; "$root/build/bin/cellform" params | tail -n +2; } > "$doc.new"
mv "$doc.new" "$doc"
