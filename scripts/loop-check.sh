#!/usr/bin/env bash
# Does loop closing make a run worse? The main job (avm-map) with INI as it is
# and with `loop_closure` turned the other way, on sequences beside those of
# scripts/odometry-sequences.sh: the whole rgbd_bonn_crowd, its every 2nd
# frame (from frame 0 and from frame 1), every 3rd frame (from frame 1 and from
# frame 2) and every 4th (from frame 0), and
# sub300 and the whole sequence with people left unmasked (the odometry then
# tracks people too and drifts: what loops are for). Prints a markdown table,
# for each sequence the ATE RMSE [m] and the loops closed, off and on, and the
# commands that made it. Needs the whole sequence in datasets/
# (scripts/get-data.sh --whole-sequence).
# Usage: scripts/loop-check.sh [INI]   (default ini/default.ini)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${AVM_BUILD_DIR:-$root/build}
ini=${1:-ini/default.ini}
out=output/loop-check  # relative to the root, as the printed commands are
work=$root/$out

source "$root/scripts/prepare.sh"
avm_prepare "$build" -DCMAKE_BUILD_TYPE=Release avm-map avm-eval >&2
whole=$(avm_required_whole_sequence "$build" loop-check)
cd "$root"
mkdir -p "$work"

# thinned STRIDE OFFSET: the whole sequence's colour frames i with
# i % STRIDE == OFFSET (each takes the nearest depth frame), made once.
thinned() {
  local name=whole-every$1-from$2 dir=$work/whole-every$1-from$2
  if [ ! -f "$work/$name.rawlog" ]; then
    local source
    source=$(readlink -f datasets/rgbd_bonn_crowd)
    rm -rf "$dir" && mkdir -p "$dir"
    ln -s "$source/rgb" "$dir/rgb" && ln -s "$source/depth" "$dir/depth"
    cp "$source/depth.txt" "$source/groundtruth.txt" "$dir/"
    awk -v k="$1" -v o="$2" '/^#/ {print; next} {if (n % k == o) print; n++}' "$source/rgb.txt" >"$dir/rgb.txt"
    "$build/bin/avm-tum2rawlog" -q --camera bonn --gt-body bonn --embed-images --compression 0 \
      --trim-to-ground-truth "$dir" "$work/$name.rawlog" >&2
  fi
  echo "$out/$name.rawlog"
}

key=$(awk -F'[ =]+' '$1 == "loop_closure" {print $2; exit}' "$ini")
case $key in
  true) flipped=false ;;
  false) flipped=true ;;
  *) echo "loop-check: $ini has no loop_closure = true|false line" >&2; exit 1 ;;
esac
# name|rawlog|extra avm-map options
sequences=(
  "bonn_crowd_sub300|datasets/bonn_crowd_sub300.rawlog|"
  "rgbd_bonn_crowd|$whole|"
  "whole every 2nd from 0|$(thinned 2 0)|"
  "whole every 2nd from 1|$(thinned 2 1)|"
  "whole every 3rd from 1|$(thinned 3 1)|"
  "whole every 3rd from 2|$(thinned 3 2)|"
  "whole every 4th from 0|$(thinned 4 0)|"
  "bonn_crowd_sub300, people unmasked|datasets/bonn_crowd_sub300.rawlog|--set odometry:mask_people=false"
  "rgbd_bonn_crowd, people unmasked|$whole|--set odometry:mask_people=false"
)
bin=${build#"$root/"}/bin
commands=()
echo "avm-map (the main job) with $ini: ATE RMSE [m], SE(3)-aligned, and loops closed, with loop_closure = $key" \
  "(as the ini has it) and = $flipped; $(date -u +%F), $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores"
echo
echo "| sequence | ATE, loop_closure = $key | loops closed | ATE, loop_closure = $flipped | loops closed |"
echo "|---|---|---|---|---|"
n=0
for s in "${sequences[@]}"; do
  IFS='|' read -r name rawlog extra <<<"$s"
  ground=${rawlog%.rawlog}_groundtruth.txt
  row="| $name |"
  for value in "$key" "$flipped"; do
    dir=$out/run$n-$value
    # shellcheck disable=SC2206  # the extra options are words
    run=("$bin/avm-map" -q -c "$ini" --set "odometry:loop_closure=$value" $extra -r "$rawlog" -o "$dir")
    evaluate=("$bin/avm-eval" "$dir/trajectory.txt" "$ground")
    commands+=("${run[*]}" "${evaluate[*]}")
    "${run[@]}" >/dev/null
    row+=" $("${evaluate[@]}" | awk '$1 == "ATE" {print $3}') | $(grep -c 'loop closed' "$dir/avm-map.log" || true) |"
  done
  echo "$row"
  n=$((n + 1))
done
echo
echo '```'
echo "scripts/loop-check.sh $ini"
printf '%s\n' "${commands[@]}"
echo '```'
