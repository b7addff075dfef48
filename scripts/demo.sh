#!/usr/bin/env bash
# Installs what is missing, builds, prepares the default dataset and model, and
# runs the main job on it. Usage: scripts/demo.sh [OUTPUT_DIR]   (default: output/)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${AVM_BUILD_DIR:-$root/build}
out=${1:-$root/output}

source "$root/scripts/prepare.sh"
avm_prepare "$build" -DCMAKE_BUILD_TYPE=Release
"$build/bin/avm-map" --config "$root/ini/default.ini" --rawlog "$rawlog" --out "$out"
echo
echo "demo: outputs in $out"
echo "  octovis $out/map_low.bt $out/map_high.bt     # the two trees"
echo "  SceneViewer3D $out/map.3Dscene               # both resolutions in one scene"
echo "  $out/map_top.png, $out/map_perspective.png   # pictures"
echo "  $out/stats.json, $out/trajectory.txt (TUM), $out/detections.txt, $out/avm-map.log"
