#!/bin/sh
# cellform-bench's command line: a bad option is refused before any benchmark runs, with exit 2 and a
# message naming it, and no file left; one short benchmark's table row and JSON. Usage: cli_test.sh PATH-TO-cellform-bench
bench="$1"
fail=0
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cd "$dir" || exit 1  # the refusals below name files here: none may be left
expect() {  # expect EXIT-CODE MESSAGE ARGS...
  code=$1
  msg=$2
  shift 2
  out=$(timeout -s KILL 60 "$bench" "$@" 2>&1)
  got=$?
  if [ "$got" -ne "$code" ] || ! printf '%s' "$out" | grep -qF -- "$msg"; then
    echo "FAIL: cellform-bench $* exited $got (want $code) and said: $out (want: $msg)"
    fail=1
  fi
}
one='cells.step.1m.t1$'  # would take a minute: each refusal must come first
expect 2 "--repetitions needs a whole number from 1 to 1000000, got 'abc'" "$one" --repetitions abc
expect 2 "--repetitions needs a whole number from 1 to 1000000, got '0'" "$one" --repetitions 0
expect 2 "--repetitions needs a whole number from 1 to 1000000, got '-3'" "$one" --repetitions -3
expect 2 "--repetitions needs a whole number from 1 to 1000000, got '2x'" "$one" --repetitions 2x
expect 2 "--repetitions needs a whole number from 1 to 1000000, got ' 3'" "$one" --repetitions ' 3'
expect 2 "--repetitions needs a whole number from 1 to 1000000, got '+3'" "$one" --repetitions +3
expect 2 "--repetitions needs a value" "$one" --repetitions
expect 2 "--json needs a value" "$one" --json
expect 2 "--json '/nonexistent-cellform/x.json' is in a folder that does not exist" "$one" --json /nonexistent-cellform/x.json
expect 2 "--json '/' is a folder" "$one" --json /
expect 2 "--json '' is empty" "$one" --json ''
expect 2 "--json '/proc/x.json' is in a folder where no file can be made" "$one" --json /proc/x.json
expect 2 "unknown option '--fast'" "$one" --fast
expect 2 "no benchmark matches" no.such.benchmark
expect 2 "--json is given twice" "$one" --json a.json --json b.json
expect 2 "--repetitions is given twice" "$one" --repetitions 1 --repetitions 2
expect 2 "an empty NAME-PREFIX ('') matches every benchmark" ''
expect 2 "an empty NAME-PREFIX ('\$') matches every benchmark" '$'
expect 0 "cells.step.1m.t1" --list
# --list lists what the prefixes choose
listed=$("$bench" --list cells.step.1m)
if ! printf '%s\n' "$listed" | grep -q "^cells.step.1m.t1" || printf '%s\n' "$listed" | grep -qv "^cells.step.1m"; then
  echo "FAIL: cellform-bench --list cells.step.1m listed: $listed"
  fail=1
fi
expect 2 "no benchmark matches" --list no.such.benchmark
expect 2 "--json needs a value, got the option '--list'" "$one" --json --list
if [ -n "$(ls -A "$dir")" ]; then
  echo "FAIL: the refusals left files: $(ls -A "$dir")"
  fail=1
fi
# a real run: the table's row, and the JSON with the median of 2 repetitions (about a second)
out=$(timeout -s KILL 100 "$bench" 'cells.step.50k.t1$' --repetitions 2 --json "$dir/r.json" 2>&1)
if [ $? -ne 0 ] || ! printf '%s\n' "$out" | grep -Eq '^cells.step.50k.t1 +[0-9.e+]+ +[0-9.e+]+ +[0-9.e+]+  steps/s$'; then
  echo "FAIL: cellform-bench cells.step.50k.t1 said: $out"
  fail=1
fi
for field in '"complete": true' '"name": "cells.step.50k.t1"' '"repetitions": 2' '"unit": "steps/s"' '"min":' '"max":' '"value":'; do
  grep -qF -- "$field" "$dir/r.json" || { echo "FAIL: r.json lacks $field: $(cat "$dir/r.json")"; fail=1; }
done
# a sweep stopped before its first result leaves a file that says so, not an earlier sweep's "complete": true
timeout -s INT 1 "$bench" 'cells.step.1m.t1$' --json "$dir/r.json" >/dev/null 2>&1
if ! grep -qF '"complete": false' "$dir/r.json" || ! grep -qF '"results": []' "$dir/r.json"; then
  echo "FAIL: after an interrupted sweep r.json holds: $(cat "$dir/r.json")"
  fail=1
fi
exit $fail
