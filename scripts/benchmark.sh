#!/usr/bin/env bash
# End-to-end benchmark of avm-map on the default dataset (odometry + detection
# + map, all 300 frames at 640x480, ini/default.ini, three times), the default
# against YOLOX-Nano's native input and against no read-ahead, and a long run (the
# sequence replayed 10 times, 3000 frames, ground-truth poses), written to
# doc/performance.md with the commands and the machine.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${AVM_BUILD_DIR:-$root/build}
out=$root/output/benchmark
doc=$root/doc/performance.md

source "$root/scripts/prepare.sh"
avm_prepare "$build" -DCMAKE_BUILD_TYPE=Release avm-map

run() {  # run NAME ARGS... : prints the command and avm-map's summary
  local name=$1; shift
  local cmd=(build/bin/avm-map -q -c ini/default.ini -r datasets/bonn_crowd_sub300.rawlog -o "output/benchmark/$name" "$@")
  echo "\`\`\`"
  echo "${cmd[*]}"
  (cd "$root" && "${cmd[@]}" | grep -vE '^ done\.$|^outputs in')
  echo "\`\`\`"
}

field() {  # field RUN KEY : a top-level number from the run's stats.json
  tr -d '\n ' < "$out/$1/stats.json" | sed -E "s/.*\"$2\":([-0-9.eE+]+).*/\1/"
  echo
}
stage() {  # stage RUN NAME : mean_ms of one stage
  tr -d '\n ' < "$out/$1/stats.json" | sed -E "s/.*\"$2\":\{\"mean_ms\":([-0-9.eE+]+).*/\1/" | awk '{printf "%.1f", $1}'
}

tmp=$(mktemp "$root/doc/.performance.XXXX")
{
  echo "# End-to-end performance"
  echo
  echo "Made by \`scripts/benchmark.sh\` on $(date -u '+%Y-%m-%d %H:%M UTC'): $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores, $(free -g | awk '/Mem:/{print $2}') GiB, load average before the runs $(cut -d' ' -f1-3 /proc/loadavg)."
  echo "Release build. Every figure below is printed by the command above it (also in \`output/benchmark/*/stats.json\`)."
  echo
  echo "## The default run: odometry + detection every third frame on a worker thread + region map"
  echo
  echo "Targets: at least 30 frames per second over all 300 frames (real-time factor >= 1 for this 30 Hz camera), peak memory below 1 GB."
  echo
  echo "Three runs of the same command, to show the spread:"
  echo
  run default
  run default-2
  run default-3
  echo
  echo "## What the default's speed settings buy"
  echo
  echo "The default detects at 320x256 (a 640x480 frame letterboxed to 320x240 and 16 rows of padding) and reads frames ahead on a thread of its own. YOLOX-Nano's native 416x416 input, and reading on the main loop's thread:"
  echo
  run input-416 --set detection:input_width=416 --set detection:input_height=416
  run no-read-ahead --set pipeline:read_ahead_frames=0
  echo
  echo "## Detection on every frame, synchronous (the slowest setting)"
  echo
  run every-frame --set pipeline:detect_every_n=1 --set pipeline:async_detection=false
  echo
  echo "## Long run: the sequence 10 times in one process (3000 frames), ground-truth poses"
  echo
  echo "Peak memory after each replay is in \`output/benchmark/long-run/stats.json\` (\`peak_memory_mb_per_replay\`):"
  echo
  run long-run --poses gt --set pipeline:repeat=10
  echo
  echo "Peak memory per replay [MiB]: $(tr -d '\n ' < "$out/long-run/stats.json" | sed -E 's/.*"peak_memory_mb_per_replay":\[([^]]*)\].*/\1/')"
  echo
  echo "## Against the targets"
  echo
  echo "| target | the three default runs |"
  echo "|---|---|"
  echo "| >= 30 frames per second, detection on at least every third frame | $(for r in default default-2 default-3; do field "$r" fps; done | awk '{printf "%s%.1f", (NR > 1 ? ", " : ""), $1; n+=($1>=30)} END {printf " fps: met in %d of 3", n}') |"
  echo "| peak memory < 1 GB | $(for r in default default-2 default-3; do field "$r" peak_memory_mb; done | awk '{printf "%s%.0f", (NR > 1 ? ", " : ""), $1; n+=($1<1024)} END {printf " MiB: met in %d of 3", n}') |"
  echo
  echo "Mean stage times of the three runs [ms] (odometry / detection per run / map), which show how fast the machine was: $(for r in default default-2 default-3; do echo "$(stage "$r" odometry) / $(stage "$r" detection) / $(stage "$r" map)"; done | paste -sd';' | sed 's/;/; /g')."
} > "$tmp"
mv "$tmp" "$doc"
cat "$doc"
