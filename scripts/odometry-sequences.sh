#!/usr/bin/env bash
# The odometry on more than one sequence: bonn_crowd_sub300 and four
# sequences made from it: every 2nd frame (from frame 0, and from frame 1) and
# every 3rd frame, the same office at two and three times the camera's speed;
# and the 300 frames played forward then backward (599 frames, the camera sees
# its start again: loops close). One sequence says little about a change to
# the odometry: moving one keyframe moves every later pose, and the ATE of 300
# frames shifts by tens of percent with it (doc/odometry.md, "Results"). Prints a markdown table, the ATE RMSE [m] of each ini on each
# sequence, the forward-backward end pose's error, sub300's frame-to-frame
# error and the median acceleration of its estimated camera (a hand-held
# camera's is a fraction of g, the ground truth's is printed beside it: what
# the estimate has beyond that is frame-to-frame noise, whatever the
# calibration between camera and ground truth), and the commands that made it.
# With --pipeline, each ini runs the main job instead, `avm-map -c INI`
# (odometry, person detection and the map; person boxes reach the odometry a
# fixed lag after their frame, where avm-odometry detects in every frame), and
# its trajectory.txt is evaluated the same way.
# Where the whole rgbd_bonn_crowd is in datasets/ (scripts/get-data.sh
# --whole-sequence), it is a sixth sequence (926 frames, 31 s; made into
# datasets/rgbd_bonn_crowd.rawlog once), with its largest frame-to-frame error.
# Usage: scripts/odometry-sequences.sh [--pipeline] [INI...]   (default ini/default.ini)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${AVM_BUILD_DIR:-$root/build}
out=output/odometry-sequences  # relative to the root, as the printed commands are
work=$root/$out
# The program each ini runs: its build target and how the caption names it.
pipeline= target=avm-odometry-app program=avm-odometry
if [ "${1:-}" = --pipeline ]; then pipeline=--pipeline target=avm-map program="avm-map (the main job)"; shift; fi
inis=("$@")
[ ${#inis[@]} -gt 0 ] || inis=(ini/default.ini)

source "$root/scripts/prepare.sh"
avm_prepare "$build" -DCMAKE_BUILD_TYPE=Release "$target" avm-eval >&2
dataset=$root/datasets/bonn_crowd_sub300
truth=$root/datasets/bonn_crowd_sub300_groundtruth.txt  # the camera's, one pose a frame

# sequence NAME BODY WRITER [ARGS...]: the rawlog NAME (and its ground truth)
# made once from the dataset's images and what `WRITER ARGS... DIR` writes into
# DIR: associations.txt and groundtruth.txt, the latter the pose of the body
# BODY (avm-tum2rawlog --gt-body).
sequence() {
  local name=$1 body=$2 dir=$work/$1
  shift 2
  [ -f "$work/$name.rawlog" ] && [ -f "$work/${name}_groundtruth.txt" ] && return
  rm -rf "$dir" && mkdir -p "$dir"
  for f in rgb depth; do ln -s "$(readlink -f "$dataset/$f")" "$dir/$f"; done
  "$@" "$dir"
  "$build/bin/avm-tum2rawlog" -q --camera bonn --gt-body "$body" --embed-images --compression 0 \
    "$dir" "$work/$name.rawlog" >&2
}
# every STRIDE OFFSET DIR: the frames i with i % STRIDE == OFFSET, with the
# dataset's own ground truth (the motion-capture body's).
every() {
  ln -s "$(readlink -f "$dataset/groundtruth.txt")" "$3/groundtruth.txt"
  awk -v k="$1" -v o="$2" '/^#/ {next} {if (n % k == o) print; n++}' \
    "$dataset/associations.txt" >"$3/associations.txt"
}
# forward_backward DIR: frames 0..N-1, then N-2..0, re-stamped at the
# sequence's mean rate; each frame keeps its camera pose from the converted
# ground truth (one line a frame, at the frame's depth timestamp), stamped anew.
# The same sequence as test-pipeline-loops' forward_backward.rawlog.
forward_backward() {
  awk -v truthout="$1/groundtruth.txt" '
    FNR == NR { if ($0 !~ /^#/) pose[g++] = $0; next }
    !/^#/ { line[n++] = $0 }
    END {
      if (n != g) { print "forward_backward: " n " frames, " g " poses" > "/dev/stderr"; exit 1 }
      split(line[0], first, " "); split(line[n - 1], last, " ")
      dt = (last[3] - first[3]) / (n - 1)
      for (i = 0; i < 2 * n - 1; i++) {
        j = i < n ? i : 2 * n - 2 - i
        split(line[j], f, " "); split(pose[j], p, " ")
        t = sprintf("%.6f", first[3] + i * dt)
        print t, f[2], t, f[4]
        print t, p[2], p[3], p[4], p[5], p[6], p[7], p[8] > truthout
      }
    }' "$truth" "$dataset/associations.txt" >"$1/associations.txt"
}
mkdir -p "$work"
sequence every2nd bonn every 2 0
sequence every2nd-odd bonn every 2 1
sequence every3rd bonn every 3 0
sequence forward-backward none forward_backward
whole=$(avm_whole_sequence "$build") || whole=

cd "$root"
header="| ini |" rule="|---|"
rawlogs=(datasets/bonn_crowd_sub300.rawlog)
for s in every2nd every2nd-odd every3rd forward-backward; do rawlogs+=("$out/$s.rawlog"); done
[ -z "$whole" ] || rawlogs+=(datasets/rgbd_bonn_crowd.rawlog)
for r in "${rawlogs[@]}"; do header+=" $(basename "$r" .rawlog) |"; rule+="---|"; done
header+=" forward-backward end | bonn_crowd_sub300 frame to frame | bonn_crowd_sub300 acceleration |"
rule+="---|---|---|"
if [ -n "$whole" ]; then header+=" rgbd_bonn_crowd largest step |"; rule+="---|"; fi
rows=() commands=()
bin=${build#"$root/"}/bin
# The true camera's acceleration, for the caption: the ground truth against itself.
commands+=("$bin/avm-eval ${truth#"$root/"} ${truth#"$root/"}")
truthAcceleration=$("$bin/avm-eval" "$truth" "$truth" | awk '$1 == "accel" && $2 == "rmse" {print $7}')
for ini in "${inis[@]}"; do
  row="| $ini |" end= frameToFrame= acceleration= largestStep=
  for rawlog in "${rawlogs[@]}"; do
    name=$(basename "$rawlog" .rawlog)
    ground=${rawlog%.rawlog}_groundtruth.txt
    if [ -n "$pipeline" ]; then
      trajectory=$out/pipeline-$(basename "$ini" .ini)-$name/trajectory.txt
      run=("$bin/avm-map" -q -c "$ini" -r "$rawlog" -o "$(dirname "$trajectory")")
    else
      trajectory=$out/$(basename "$ini" .ini)-$name.txt
      run=("$bin/avm-odometry" -c "$ini" "$rawlog" "$trajectory")
    fi
    # One avm-eval a run: the ATE does not depend on the RPE's time step, and
    # 0.03 s makes the RPE the error from one frame to the next.
    evaluate=("$bin/avm-eval" --rpe-delta 0.03 "$trajectory" "$ground")
    commands+=("${run[*]}" "${evaluate[*]}")
    "${run[@]}" >/dev/null
    report=$("${evaluate[@]}")
    row+=" $(awk '$1 == "ATE" {print $3}' <<<"$report") |"
    case $name in
      bonn_crowd_sub300)
        frameToFrame=$(awk '$1 == "RPE" && $2 == "trans" {print $4}' <<<"$report")
        acceleration=$(awk '$1 == "accel" && $2 == "rmse" {print $7}' <<<"$report") ;;
      rgbd_bonn_crowd) largestStep=" $(awk '$1 == "step" {print $10}' <<<"$report") |" ;;
      # Its last frame is frame 0 again, where the run started at the ground truth.
      forward-backward)
        end=$(awk 'FNR == NR { if (!/^#/ && !n++) split($0, start, " "); next } !/^#/ { split($0, p, " ") }
          END { printf "%.4f", sqrt((p[2] - start[2])^2 + (p[3] - start[3])^2 + (p[4] - start[4])^2) }' \
          "$ground" "$trajectory") ;;
    esac
  done
  rows+=("$row $end | $frameToFrame | $acceleration |$largestStep")
done
echo "$program:" \
  "ATE RMSE [m], SE(3)-aligned; forward-backward end: the last pose's distance from the ground truth [m]" \
  "(not aligned); frame to frame: RPE RMSE over one frame (33.5 ms) [m/s]; acceleration: the median of the" \
  "estimated camera centre's [m/s^2] (the ground truth's: $truthAcceleration);" \
  "${largestStep:+largest step: the largest error, over the whole sequence, of the motion from one frame to the next [m];}" \
  "$(date -u +%F), $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores"
echo
echo "$header"
echo "$rule"
printf '%s\n' "${rows[@]}"
echo
echo '```'
echo "scripts/odometry-sequences.sh $pipeline${pipeline:+ }${inis[*]}"
printf '%s\n' "${commands[@]}"
echo '```'
