#!/usr/bin/env bash
# The odometry on more than one sequence: bonn_crowd_sub300 and four
# sequences made from it: every 2nd frame (from frame 0, and from frame 1) and
# every 3rd frame, the same office at two and three times the camera's speed;
# and the 300 frames played forward then backward (599 frames, the camera sees
# its start again: loops close). One sequence says little about a change to
# the odometry: moving one keyframe moves every later pose, and the ATE of 300
# frames shifts by tens of percent with it (doc/odometry.md, "More than one
# sequence"). Prints a markdown table, the ATE RMSE [m] of each ini on each
# sequence, and the commands that made it.
# Usage: scripts/odometry-sequences.sh [INI...]   (default ini/default.ini)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${AVM_BUILD_DIR:-$root/build}
work=$root/output/odometry-sequences
inis=("$@")
[ ${#inis[@]} -gt 0 ] || inis=(ini/default.ini)

source "$root/scripts/prepare.sh"
avm_prepare "$build" -DCMAKE_BUILD_TYPE=Release avm-odometry-app avm-eval >&2
dataset=$root/datasets/bonn_crowd_sub300

# make_sequence NAME STRIDE OFFSET: the frames i with i % STRIDE == OFFSET of
# the dataset's associations, as a rawlog with its ground truth.
make_sequence() {
  local name=$1 stride=$2 offset=$3 dir=$work/$1
  [ -f "$work/$name.rawlog" ] && [ -f "$work/${name}_groundtruth.txt" ] && return
  rm -rf "$dir" && mkdir -p "$dir"
  for f in rgb depth groundtruth.txt; do ln -s "$(readlink -f "$dataset/$f")" "$dir/$f"; done
  awk -v k="$stride" -v o="$offset" '/^#/ {next} {if (n % k == o) print; n++}' \
    "$dataset/associations.txt" >"$dir/associations.txt"
  "$build/bin/avm-tum2rawlog" -q --camera bonn --gt-body bonn --embed-images --compression 0 \
    "$dir" "$work/$name.rawlog" >&2
}
# make_forward_backward NAME: the dataset played forward, then backward to its
# first frame (599 frames), so that the camera shows its start again and loops
# can close; frames re-stamped at the sequence's mean rate, the ground truth
# interpolated at each frame's own time (depth timestamp, as avm-tum2rawlog
# stamps frames) and written at its new one. The same sequence as
# test-pipeline-loops' forward_backward.rawlog.
make_forward_backward() {
  local name=$1 dir=$work/$1
  [ -f "$work/$name.rawlog" ] && [ -f "$work/${name}_groundtruth.txt" ] && return
  rm -rf "$dir" && mkdir -p "$dir"
  for f in rgb depth; do ln -s "$(readlink -f "$dataset/$f")" "$dir/$f"; done
  awk -v gtout="$dir/groundtruth.txt" '
    BEGIN { g = 0; n = 0 }
    FNR == NR { if ($0 !~ /^#/) { gt[g] = $0; gtt[g++] = $1 }; next }
    /^#/ { next }
    { line[n] = $0; t[n++] = $3 }
    function pose_at(s,   a, b, u, i, A, B, q, d, len) {
      for (a = 0; a + 1 < g && gtt[a + 1] <= s; a++) {}
      b = (a + 1 < g) ? a + 1 : a
      u = (gtt[b] > gtt[a]) ? (s - gtt[a]) / (gtt[b] - gtt[a]) : 0
      split(gt[a], A, " "); split(gt[b], B, " ")
      d = A[5] * B[5] + A[6] * B[6] + A[7] * B[7] + A[8] * B[8]
      out = ""
      for (i = 2; i <= 4; i++) out = out sprintf(" %.9f", A[i] + u * (B[i] - A[i]))
      len = 0
      for (i = 5; i <= 8; i++) { q[i] = A[i] + u * ((d < 0 ? -B[i] : B[i]) - A[i]); len += q[i] * q[i] }
      for (i = 5; i <= 8; i++) out = out sprintf(" %.10f", q[i] / sqrt(len))
      return out
    }
    END {
      dt = (t[n - 1] - t[0]) / (n - 1)
      for (i = 0; i < 2 * n - 1; i++) {
        j = (i < n) ? i : 2 * n - 2 - i
        split(line[j], f, " ")
        s = sprintf("%.6f", t[0] + i * dt)
        print s, f[2], s, f[4]
        print s pose_at(t[j]) > gtout
      }
    }' "$dataset/groundtruth.txt" "$dataset/associations.txt" >"$dir/associations.txt"
  "$build/bin/avm-tum2rawlog" -q --camera bonn --gt-body bonn --embed-images --compression 0 \
    "$dir" "$work/$name.rawlog" >&2
}
mkdir -p "$work"
make_sequence every2nd 2 0
make_sequence every2nd-odd 2 1
make_sequence every3rd 3 0
make_forward_backward forward-backward

sequences=("sub300:datasets/bonn_crowd_sub300.rawlog:datasets/bonn_crowd_sub300_groundtruth.txt")
for s in every2nd every2nd-odd every3rd forward-backward; do
  sequences+=("$s:output/odometry-sequences/$s.rawlog:output/odometry-sequences/${s}_groundtruth.txt")
done

cd "$root"
header="| ini |" rule="|---|"
for s in "${sequences[@]}"; do header+=" ${s%%:*} |"; rule+="---|"; done
rows=() commands=()
for ini in "${inis[@]}"; do
  row="| $ini |"
  for s in "${sequences[@]}"; do
    IFS=: read -r name rawlog truth <<<"$s"
    trajectory=$work/$(basename "$ini" .ini)-$name.txt
    cmd=("$build/bin/avm-odometry" -c "$ini" "$rawlog" "$trajectory")
    "${cmd[@]}" >/dev/null
    commands+=("${cmd[*]#"$root/"}" "build/bin/avm-eval ${trajectory#"$root/"} $truth")
    row+=" $("$build/bin/avm-eval" "$trajectory" "$truth" | awk '$1 == "ATE" {print $3}') |"
  done
  rows+=("$row")
done
echo "ATE RMSE [m], SE(3)-aligned; $(date -u +%F), $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores"
echo
echo "$header"
echo "$rule"
printf '%s\n' "${rows[@]}"
echo
echo '```'
echo "scripts/odometry-sequences.sh ${inis[*]}"
printf '%s\n' "${commands[@]}"
echo '```'
