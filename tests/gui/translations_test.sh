#!/usr/bin/env bash
# lupdate over the workbench's sources into copies of translations/*.ts: every language must have
# at least 95 % of the strings it finds translated (no "unfinished" entries beyond 5 %).
set -euo pipefail
lupdate=$1
src=$2
shift 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0
for ts in "$src"/translations/relume_*.ts; do
  cp "$ts" "$tmp/"
  copy="$tmp/$(basename "$ts")"
  "$lupdate" -silent -no-obsolete -locations none "$@" -ts "$copy" >/dev/null
  total=$(grep -c '<source>' "$copy")
  open=$(grep -c 'type="unfinished"' "$copy" || true)
  pct=$(( (total - open) * 100 / total ))
  echo "$(basename "$ts"): $((total - open)) of $total strings translated ($pct %)"
  [ "$total" -gt 0 ] && [ $(( (total - open) * 100 )) -ge $(( 95 * total )) ] || status=1
done
exit $status
