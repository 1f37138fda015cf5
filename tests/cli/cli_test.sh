#!/usr/bin/env bash
# End-to-end: the relume command on the sample room, as a user runs it.
set -u
relume=$1
room=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
check() { if eval "$2"; then echo "ok: $1"; else echo "FAILED: $1"; fail=1; fi; }

"$relume" solve "$room" --json "$tmp/solve.json" 2>"$tmp/solve.err"
check "solve exits 0" "[ $? -eq 0 ]"
check "solve prints progress" "grep -q 'refinement round' '$tmp/solve.err'"
check "solve JSON lists polygons with radiosity and irradiance" \
  "python3 -c \"import json,sys; d=json.load(open('$tmp/solve.json')); p={x['name']:x for x in d['polygons']}; \
assert p['floor']['radiosity'][0] > 0 and p['floor']['irradiance'][0] > p['floor']['radiosity'][0]; \
t=d['totals']; assert all(k in t for k in ['elements','leaves','links','rays','seconds','peak_memory_bytes'])\""

"$relume" render "$room" --camera main -o "$tmp/main.png" 2>/dev/null
check "render writes a PNG" "[ -s '$tmp/main.png' ]"
"$relume" render "$room" --camera view2 -o "$tmp/leaves.exr" --show leaves 2>/dev/null
check "render --show leaves writes an EXR" "[ -s '$tmp/leaves.exr' ]"

"$relume" render "$room" --camera nosuch -o "$tmp/x.png" 2>"$tmp/err.txt"
check "unknown camera is an error naming it" "[ $? -eq 1 ] && grep -q \"camera 'nosuch'\" '$tmp/err.txt'"
check "and writes nothing" "[ ! -e '$tmp/x.png' ]"

"$relume" solve "$tmp/nowhere" --json "$tmp/y.json" 2>"$tmp/err2.txt"
check "missing room is an error naming it" "[ $? -eq 1 ] && grep -q 'nowhere' '$tmp/err2.txt'"

"$relume" import "$room" -o "$tmp/sample.relume" 2>/dev/null
"$relume" solve "$tmp/sample.relume" --json "$tmp/proj.json" 2>/dev/null
check "a written project solves like its bundle" \
  "python3 -c \"import json; a=json.load(open('$tmp/solve.json')); b=json.load(open('$tmp/proj.json')); \
assert [p['radiosity'] for p in a['polygons']] == [p['radiosity'] for p in b['polygons']]\""

# Ctrl-C during a long solve: exit 130, no output file, no temporary left behind.
"$relume" solve "$room" --json "$tmp/cancel.json" --eps 0.0005 --min-area 0.0002 2>"$tmp/cancel.err" &
pid=$!
sleep 1.5
kill -INT $pid
wait $pid
code=$?
check "Ctrl-C cancels with exit 130" "[ $code -eq 130 ]"
check "and leaves no file" "[ -z \"\$(ls '$tmp' | grep cancel.json)\" ]"

if [ $fail -eq 0 ]; then echo "cli: all passed"; fi
exit $fail
