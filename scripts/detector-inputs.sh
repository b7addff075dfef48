#!/usr/bin/env bash
# The detector's input size against what it finds and what it costs: YOLOX-Nano
# (ini/detect.ini) at several network inputs over the 300 frames of the default
# rawlog, with avm-detect's benchmark (1 and 2 OpenCV threads), and the default
# input with the model's graph as exported (simplify_graph = false), written to
# doc/detector-inputs.md with the commands and the machine.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${AVM_BUILD_DIR:-$root/build}
doc=$root/doc/detector-inputs.md

source "$root/scripts/prepare.sh"
avm_prepare "$build" -DCMAKE_BUILD_TYPE=Release avm-detect
madeBy=$(avm_made_by)  # before the runs: their machine and its load

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
tmp=$(mktemp "$root/doc/.detector-inputs.XXXX")
{
  echo "# Detector input size: persons found and time"
  echo
  echo "$madeBy"
  echo
  echo "YOLOX-Nano on the 300 colour frames of \`datasets/bonn_crowd_sub300.rawlog\`, \`ini/detect.ini\` with only the input size changed, and last the default input with the model's graph as exported (\`simplify_graph = false\`: doc/detection.md says what the rewrite does). The 640x480 frame is letterboxed: scaled by min(width/640, height/480), the rest padded. Persons nearer than the depth range (6 m) are at least ~60 px tall at 256x192."
  echo
  # The last run is the default input with the model's graph as exported
  # (simplify_graph = false): what the rewrite of doc/detection.md saves.
  for run in 416x416 320x320 320x256 256x192 256x192:as-exported; do
    size=${run%%:*} w=${run%%x*} h=${size#*x}
    keys="input_width = $w, input_height = $h" extra=
    if [ "$run" != "$size" ]; then keys+=", simplify_graph = false" extra=$'simplify_graph = false\n'; fi
    # [detection] is detect.ini's last section: the keys appended go to it.
    { cat "$root/ini/detect.ini"; printf 'input_width = %s\ninput_height = %s\n%s' "$w" "$h" "$extra"; } > "$work/detect-$run.ini"
    if [ "$run" = "$size" ]; then echo "### $size"; else echo "### $size, the model's graph as exported"; fi
    echo
    echo "\`\`\`"
    echo "build/bin/avm-detect -c ini/detect.ini ($keys) --rawlog datasets/bonn_crowd_sub300.rawlog --bench"
    echo "\`\`\`"
    echo
    (cd "$root" && "$build/bin/avm-detect" -c "$work/detect-$run.ini" --rawlog datasets/bonn_crowd_sub300.rawlog --bench 2>/dev/null)
    echo
  done
} > "$tmp"
mv "$tmp" "$doc"
cat "$doc"
