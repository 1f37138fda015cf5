#!/usr/bin/env bash
# Build and run the whole test suite (every tier: quick, unit, e2e, gui; see README).
# Each phase's wall time is printed at the end, and appended to $RELUME_PHASE_LOG when set (.ci/run).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/phase.sh
phase build bash scripts/build.sh
phase suite ctest --test-dir build --output-on-failure -j "$(nproc)"
