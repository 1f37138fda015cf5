#!/usr/bin/env bash
# scripts/fuzz.sh NAME SECONDS: runs the libFuzzer harness tests/fuzz/NAME.cpp for SECONDS
# (clang++-14 with ASan + UBSan, into build-fuzz/), starting from the seeds in
# tests/fuzz/corpus/NAME and growing a working corpus in build-fuzz/corpus/NAME. A crash, leak or
# hang (> 1 s per input) stops it and is written to build-fuzz/crashes/NAME/; minimise it
# (fuzz_NAME -minimize_crash=1 FILE) and commit it under tests/fuzz/regressions/NAME/, where CI
# replays it. Needs Debian's clang-14 and libclang-rt-14-dev.
set -euo pipefail
cd "$(dirname "$0")/.."
name=${1:?usage: scripts/fuzz.sh NAME SECONDS}
seconds=${2:-60}
[ -f "tests/fuzz/$name.cpp" ] || { echo "scripts/fuzz.sh: no harness tests/fuzz/$name.cpp" >&2; exit 2; }
command -v clang++-14 > /dev/null || { echo "scripts/fuzz.sh: clang++-14 is missing (apt-get install clang-14 libclang-rt-14-dev)" >&2; exit 2; }
cmake -S tests/fuzz -B build-fuzz -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 > /dev/null
cmake --build build-fuzz --target "fuzz_$name"
mkdir -p "build-fuzz/corpus/$name" "build-fuzz/crashes/$name"
cp -n "tests/fuzz/corpus/$name"/* "build-fuzz/corpus/$name/" 2> /dev/null || true
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
"build-fuzz/fuzz_$name" -max_total_time="$seconds" -timeout=1 -rss_limit_mb=2048 -print_final_stats=1 \
  -artifact_prefix="build-fuzz/crashes/$name/" "build-fuzz/corpus/$name" "tests/fuzz/corpus/$name"
