#!/usr/bin/env bash
# Debian 12 packages Relume builds and runs with (skipped when all are present).
set -euo pipefail
pkgs=(cmake ninja-build ccache g++ pkg-config python3
      qt6-base-dev libglm-dev libtbb-dev libembree-dev
      libopenimageio-dev openimageio-tools libopencv-dev libgtest-dev colmap
      libqt6sql6-sqlite
      libqt6opengl6-dev libgl-dev libxkbcommon-dev qt6-tools-dev qt6-tools-dev-tools
      qt6-l10n-tools libgl1-mesa-dri xvfb xauth
      libvtk9-dev qt6-charts-dev libceres-dev zlib1g-dev)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO=sudo
  $SUDO apt-get update
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
fi
