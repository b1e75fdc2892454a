#!/bin/sh
# scripts/preview.py as a user runs it: a preview of a small run, and one-line refusals (exit 2 for a bad
# command line, 1 for a PNG it cannot write) instead of Python tracebacks. Skipped (77) without matplotlib.
# Usage: preview_test.sh PATH-TO-cellform PATH-TO-preview.py
cellform="$1"
preview="$2"
/usr/bin/python3 -c "import matplotlib" 2>/dev/null || exit 77
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
printf 'run { steps = 0 }\ndisc { radius = 2 }\n' > "$dir/s.lua"
"$cellform" run "$dir/s.lua" --out "$dir/o" --quiet || { echo "FAIL: cellform run of the small script failed"; exit 1; }
fail=0
expect() {  # expect EXIT-CODE MESSAGE ARGS...
  code=$1
  msg=$2
  shift 2
  out=$(/usr/bin/python3 "$preview" "$@" 2>&1)
  got=$?
  if [ "$got" -ne "$code" ] || ! printf '%s' "$out" | grep -qF -- "$msg" || printf '%s' "$out" | grep -q Traceback; then
    echo "FAIL: preview.py $* exited $got (want $code) and said: $out (want: $msg)"
    fail=1
  fi
}
expect 0 "$dir/p.png" "$dir/o" "$dir/p.png"
[ -s "$dir/p.png" ] || { echo "FAIL: no PNG written"; fail=1; }
expect 0 "$dir/t.png" "$dir/o" "$dir/t.png" --top --dpi 50
expect 2 "the following arguments are required: OUT_DIR"
expect 2 "argument --dpi: 0 is not from 1 to 2000" "$dir/o" --dpi 0
expect 2 "argument --elev: invalid float value: 'abc'" "$dir/o" --elev abc
expect 2 "unrecognized arguments: --tpo" "$dir/o" "$dir/q.png" --tpo "$dir/r.png"
expect 1 "cannot write '/proc/nope/x.png'" "$dir/o" /proc/nope/x.png
expect 1 "holds neither cells.ply nor veins.ply" "$dir"
expect 1 "is not a folder (it does not exist)" "$dir/none"
expect 1 "is not a folder:" "$dir/s.lua"
exit $fail
