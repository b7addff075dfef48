#!/usr/bin/env bash
# Installs the Debian bookworm packages avm needs, only those that are missing.
# Idempotent: prints nothing and touches nothing when everything is installed.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libmrpt-dev mrpt-apps
  liboctomap-dev
  libopencv-dev
  libeigen3-dev
  libceres-dev
  libgtest-dev
  xauth xvfb          # stock GUI apps (RawLogViewer) run headless in tests
  libx11-dev          # avm-viewer: the X server's screenshot of the view (XGetImage)
  curl unzip ca-certificates   # scripts/get-data.sh without ../shared
  clang libclang-rt-14-dev   # sanitizer and fuzzing builds
  clang-format-14     # scripts/format.sh and its ctest check
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

if [ "$(id -u)" -ne 0 ]; then
  sudo_cmd=sudo
  command -v sudo >/dev/null || { echo "install-deps: missing packages (${missing[*]}) and not root, no sudo" >&2; exit 1; }
else
  sudo_cmd=
fi
echo "install-deps: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
$sudo_cmd apt-get update -qq
$sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
