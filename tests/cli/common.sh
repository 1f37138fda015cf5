# Shared by the end-to-end scripts: arguments, a scratch folder removed on exit, and check().
set -u
relume=$1
room=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
check() { if eval "$2"; then echo "ok: $1"; else echo "FAILED: $1"; fail=1; fi; }
