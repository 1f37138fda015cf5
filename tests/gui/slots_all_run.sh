#!/usr/bin/env bash
# Every test slot of a Qt Test binary is named by some ctest entry: the binary's own list
# (-functions) against the slots the entries run, given after the binary.
set -euo pipefail
binary=$1
shift
declare -A named=()
for s in "$@"; do named[$s]=1; done
missing=()
count=0
while read -r f; do
  f=${f%%(*}
  [ -z "$f" ] && continue
  count=$((count + 1))
  [ -n "${named[$f]:-}" ] || missing+=("$f")
done < <("$binary" -functions)
[ "$count" -gt 0 ] || { echo "FAILED: $binary -functions listed no slots"; exit 1; }
if [ ${#missing[@]} -gt 0 ]; then
  echo "FAILED: slots of $(basename "$binary") in no ctest entry (tests/CMakeLists.txt, relume_gui_entry): ${missing[*]}"
  exit 1
fi
echo "ok: all $count slots of $(basename "$binary") run in a ctest entry"
