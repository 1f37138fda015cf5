#!/usr/bin/env bash
# Configure (Release, Ninja, ccache) and build everything into build/.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release ${RELUME_CMAKE_ARGS:-}
cmake --build build -j "$(nproc)"
