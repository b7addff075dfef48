#!/usr/bin/env bash
# Installs what is missing, builds, prepares the default dataset and model, and
# runs the main job on it. Usage: scripts/demo.sh [OUTPUT_DIR]   (default: output/)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${AVM_BUILD_DIR:-$root/build}
out=${1:-$root/output}

"$root/scripts/install-deps.sh"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j "$(nproc)"
"$root/scripts/get-data.sh"

rawlog=$root/datasets/bonn_crowd_sub300.rawlog
if [ ! -f "$rawlog" ]; then
  "$build/bin/avm-tum2rawlog" --camera bonn --gt-body bonn "$root/datasets/bonn_crowd_sub300" "$rawlog"
fi
mkdir -p "$out"
# Stock MRPT tools find the external images only through a relative path.
(cd "$(dirname "$rawlog")" && rawlog-edit -i "$(basename "$rawlog")" --info) | tee "$out/rawlog-info.txt"
echo
echo "demo: rawlog  $rawlog (open it with: cd datasets && RawLogViewer bonn_crowd_sub300.rawlog)"
echo "demo: summary $out/rawlog-info.txt"
