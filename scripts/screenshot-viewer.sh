#!/usr/bin/env bash
# The picture of the live view in doc/viewer.md: avm-map on the default dataset
# (ini/default.ini, visual odometry, all 300 frames), then avm-view on its
# outputs, on a private X server (xvfb-run), saved by avm-view --screenshot
# (what the X server shows, GL included).
# Usage: scripts/screenshot-viewer.sh [PNG]   (default doc/viewer.png)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${AVM_BUILD_DIR:-$root/build}
png=${1:-$root/doc/viewer.png}
out=$root/output/viewer

source "$root/scripts/prepare.sh"
avm_prepare "$build" -DCMAKE_BUILD_TYPE=Release avm-map avm-view
(cd "$root" && "$build/bin/avm-map" -q -c ini/default.ini -r "$rawlog" -o "$out")
xvfb-run -a -s "-screen 0 1280x800x24" \
  "$build/bin/avm-view" --width 1200 --height 760 "$out" --screenshot "$png"
echo "screenshot-viewer: $png"
