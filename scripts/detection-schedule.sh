#!/usr/bin/env bash
# The detector scheduled by what changed in view ([pipeline] detection_schedule
# = on_change, ini/detect-on-change.ini) against the default (every third
# frame), written to doc/detection-schedule.md with the commands and the
# machine. On bonn_crowd_sub300 and, where datasets/ has it, the whole
# rgbd_bonn_crowd, three avm-map runs each, all of avm-map on the first core:
# the detector on every frame (the reference: who walks into view, and the
# first frame the detector can see them on), every third frame, on change.
# For each: the detector's runs and what started them, its CPU time a frame,
# the persons who walk in and how many frames after the reference it found
# them (avm-eval --walk-ins), the ATE. Then the ATE of both configurations on
# the six sequences of scripts/odometry-sequences.sh --pipeline: one
# sequence's ATE moves by tens of percent with any change of when the
# odometry gets its person boxes (doc/odometry.md).
# Usage: scripts/detection-schedule.sh
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${AVM_BUILD_DIR:-$root/build}
doc=$root/doc/detection-schedule.md
out=output/detection-schedule  # relative to the root, as the printed commands are

source "$root/scripts/prepare.sh"
avm_prepare "$build" -DCMAKE_BUILD_TYPE=Release avm-map avm-eval
madeBy=$(avm_made_by)  # before the runs: their machine and its load
rawlogs=(datasets/bonn_crowd_sub300.rawlog)
if whole=$(avm_whole_sequence "$build"); then rawlogs+=("${whole#"$root/"}"); fi
bin=${build#"$root/"}/bin

cd "$root"
rm -rf "$out" && mkdir -p "$out"
commands=()
# run NAME RAWLOG INI [ARGS...]: avm-map on the first core into $out/NAME.
run() {
  local name=$1 rawlog=$2 ini=$3
  shift 3
  local cmd=(taskset -c 0 "$bin/avm-map" -q -c "$ini" -r "$rawlog" -o "$out/$name" "$@")
  commands+=("${cmd[*]}")
  "${cmd[@]}" >/dev/null
}
# number RUN KEY [OBJECT]: the number KEY of RUN's stats.json (in OBJECT).
number() { avm_stat "$out/$1" "${@:2}"; }
# detectorCpu RUN: the detector's CPU time a frame [ms]: a run's on its thread, times the runs, over the frames.
detectorCpu() {
  awk -v f="$(number "$1" frames)" -v n="$(number "$1" runs detection)" -v m="$(number "$1" mean_ms detection_cpu)" \
    'BEGIN { printf "%.3f\n", m * n / f }'
}
# row SEQUENCE RUN REFERENCE: the table's row of RUN; its CPU times the
# medians of its three runs where it has them.
row() {
  local startedBy walkIns="reference | " repeats=("$2") cpu runCpu detector r
  startedBy=$(tr -d '\n ' <"$out/$2/stats.json" | sed -nE 's/.*"started_by":\{([^}]*)\}.*/\1/p' |
    tr -d '"' | sed 's/:/ /g; s/,/, /g')
  if [ "$2" != "$3" ]; then
    local cmd=("$bin/avm-eval" --walk-ins "$out/$2" "$out/$3")
    commands+=("${cmd[*]}")
    "${cmd[@]}" >"$out/$2/walk-ins.txt"
    walkIns=$(awk '/^walk-ins/ {gsub(",", ""); printf "%s of %s | %s / %s", $4, $2, $12, $14}' "$out/$2/walk-ins.txt")
    repeats+=("$2-2" "$2-3")
  fi
  cpu=$(for r in "${repeats[@]}"; do number "$r" cpu_ms_per_frame; done | avm_median)
  runCpu=$(for r in "${repeats[@]}"; do number "$r" mean_ms detection_cpu; done | avm_median)
  detector=$(for r in "${repeats[@]}"; do detectorCpu "$r"; done | avm_median)
  awk -v s="$1" -v r="$2" -v by="$startedBy" -v w="$walkIns" -v n="$(number "$2" runs detection)" -v d="$detector" \
    -v dm="$runCpu" -v t="$cpu" -v ate="$(number "$2" odometry_ate_rmse_m)" 'BEGIN {
      printf "| %s | %s | %d | %s | %.1f (%.1f a run) | %.1f | %s | %.4f |\n", s, r, n, by, d, dm, t, w, ate
    }'
}

rows=() walkInLists=()
for rawlog in "${rawlogs[@]}"; do
  name=$(basename "$rawlog" .rawlog)
  run "$name-every-frame" "$rawlog" ini/default.ini --set pipeline:detect_every_n=1
  # Three runs of each, alternately, for the medians of their CPU times.
  for repeat in "" -2 -3; do
    run "$name-every-third$repeat" "$rawlog" ini/default.ini
    run "$name-on-change$repeat" "$rawlog" ini/detect-on-change.ini
  done
  for schedule in every-third on-change; do
    for f in trajectory.txt detections.txt map_low.bt map_high.bt; do
      for repeat in -2 -3; do
        cmp -s "$out/$name-$schedule/$f" "$out/$name-$schedule$repeat/$f" ||
          { echo "detection-schedule: $out/$name-$schedule$repeat/$f differs from the first run's" >&2; exit 1; }
      done
    done
  done
  for schedule in every-frame every-third on-change; do
    rows+=("$(row "$name" "$name-$schedule" "$name-every-frame")")
  done
  for schedule in every-third on-change; do
    walkInLists+=("$name-$schedule:" "$(cat "$out/$name-$schedule/walk-ins.txt")" "")
  done
done
# The default with its boxes a frame later: how far that alone moves the ATE.
printf '[pipeline]\ndetection_lag_frames = 3\n\n[map]\nadaptiveOctoMap_count = 1\n' >"$out/default-lag3.ini"
sequences=$("$root/scripts/odometry-sequences.sh" --pipeline ini/default.ini ini/detect-on-change.ini \
  "$out/default-lag3.ini")

tmp=$(mktemp "$root/doc/.detection-schedule.XXXX")
{
  echo "# When the detector runs: every third frame, or where the view changed"
  echo
  echo "$madeBy"
  echo
  echo "\`every-third\` is \`ini/default.ini\` (\`detection_schedule = fixed\`, \`detect_every_n = 3\`); \`on-change\` is \`ini/detect-on-change.ini\` (\`detection_schedule = on_change\`: at most every third frame, where the depth moved on 1 % of the image or a tenth of it is newly in view since the detector's last frame, else every sixth; doc/detection.md); \`every-frame\` is the default with \`detect_every_n = 1\`, the reference of the walk-ins. All of avm-map on the first core."
  echo
  echo "A walk-in is a person of the reference run (its person ids) whose first box no reference box of the three frames before overlaps (IoU 0.5 or more: not a person the tracker gave a new id): someone new in view, on the first frame the detector could see them. A run found them on the first frame it ran the detector and had their box (IoU 0.5 or more with the reference's box of that frame, the person followed through the reference by id or, across a new id, by overlap). avm-eval also says on how many of the 30 frames from a walk-in the reference saw the person: one seen on a few only is found by luck, by any schedule that skips frames. Detector CPU: the CPU time of a run on its thread, times the runs, over the frames."
  echo
  echo "CPU times are the medians of three runs of each schedule, made alternately (\`-2\`, \`-3\`; the script checks that their trajectories, detections and maps are the first run's, byte for byte): this virtual machine's speed moves by several percent from minute to minute."
  echo
  echo "| sequence | run | detector runs | started by | detector CPU [ms a frame] | CPU, all threads [ms a frame] | walk-ins found | frames later: mean / most | odometry ATE RMSE [m] |"
  echo "|---|---|---:|---|---:|---:|---|---|---:|"
  printf '%s\n' "${rows[@]}"
  echo
  echo "\`\`\`"
  printf '%s\n' "${commands[@]}"
  echo "\`\`\`"
  echo
  echo "Each walk-in, as \`avm-eval --walk-ins\` prints it:"
  echo
  echo "\`\`\`"
  printf '%s\n' "${walkInLists[@]}"
  echo "\`\`\`"
  echo
  echo "## The ATE on six sequences"
  echo
  echo "\`scripts/odometry-sequences.sh --pipeline\` (doc/odometry.md): the same two configurations on bonn_crowd_sub300, four sequences made from it and the whole sequence. Changing when the odometry gets its person boxes moves one sequence's ATE by tens of percent either way: \`$out/default-lag3.ini\` is the default with every detection applied a frame later (\`detection_lag_frames = 3\`, nothing else set: the built-in defaults are ini/default.ini's). The six together say more than one."
  echo
  echo "$sequences"
} >"$tmp"
mv "$tmp" "$doc"
cat "$doc"
