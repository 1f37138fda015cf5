#!/usr/bin/env bash
# Where the suite's time goes: the slowest ctest entries of the last run and each label's total,
# read from CTest's own records in BUILD/Testing/Temporary (LastTest.log: each test's time in the
# last run, kept aside as LastRunTimes.log; CTestCostData.txt: CTest's running average per test,
# used where the log lacks one).
#   bash scripts/test-times.sh [BUILD_DIR] [N]      (defaults: build, 20)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
top=${2:-20}
[ -d "$build/Testing/Temporary" ] || { echo "test-times: $build/Testing/Temporary: no ctest run recorded there" >&2; exit 1; }
# Listing the tests (for their labels) rewrites LastTest.log, so a run's log is kept aside first.
tmp="$build/Testing/Temporary"
if grep -q "^Test time" "$tmp/LastTest.log" 2> /dev/null; then cp "$tmp/LastTest.log" "$tmp/LastRunTimes.log"; fi
ctest --test-dir "$build" --show-only=json-v1 > "$tmp/tests.json"
python3 - "$build" "$top" <<'PY'
import json, os, re, sys
build, top = sys.argv[1], int(sys.argv[2])
tmp = os.path.join(build, "Testing", "Temporary")
tests = json.load(open(os.path.join(tmp, "tests.json")))["tests"]
info = {}
for t in tests:
    props = {p["name"]: p["value"] for p in t.get("properties", [])}
    info[t["name"]] = (props.get("LABELS", []), props.get("TIMEOUT"))
times, source = {}, "LastRunTimes.log (the last complete run)"
log = os.path.join(tmp, "LastRunTimes.log")
if os.path.exists(log):
    current = None
    for line in open(log, errors="replace"):
        m = re.match(r"^\d+/\d+ Test: (.*)$", line.rstrip("\n"))
        if m:
            current = m.group(1)
            continue
        m = re.match(r"^Test time *= *([0-9.]+) sec", line.strip())
        if m and current:
            times[current] = float(m.group(1))
            current = None
cost = os.path.join(tmp, "CTestCostData.txt")
if not times and os.path.exists(cost):
    source = "CTestCostData.txt (CTest's running averages)"
    for line in open(cost):
        if line.startswith("---"):
            break
        parts = line.rsplit(" ", 2)
        if len(parts) == 3:
            times[parts[0]] = float(parts[2])
ran = {n: s for n, s in times.items() if n in info}
if not ran:
    sys.exit("test-times: no test times recorded in " + tmp)
print(f"from {source}")
print(f"{'seconds':>8} {'timeout':>7}  {'labels':<14} test   (the {min(top, len(ran))} slowest of {len(ran)})")
for name, s in sorted(ran.items(), key=lambda kv: -kv[1])[:top]:
    labels, timeout = info[name]
    to = f"{float(timeout):.0f}" if timeout else "-"
    flag = "  > half its timeout" if timeout and s > float(timeout) / 2 else ""
    print(f"{s:8.1f} {to:>7}  {','.join(labels):<14} {name}{flag}")
totals = {}
for name, s in ran.items():
    for label in info[name][0] or ["(none)"]:
        n, t = totals.get(label, (0, 0.0))
        totals[label] = (n + 1, t + s)
print(f"\n{'label':<8} {'tests':>5} {'seconds':>9}  (a test with two labels counts in both)")
for label, (n, t) in sorted(totals.items(), key=lambda kv: -kv[1][1]):
    print(f"{label:<8} {n:5d} {t:9.1f}")
print(f"{'all':<8} {len(ran):5d} {sum(ran.values()):9.1f}  (the sum of test times; with -j the wall time is less)")
PY
