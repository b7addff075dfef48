#!/usr/bin/env bash
# The fault test of checkpoints: kills avm-map with SIGKILL at random instants
# (a fixed seed: the same instants every time), checks that each killed run's
# output folder holds nothing or a checkpoint (and no other output, whole or
# partial), resumes each with `avm-map --resume DIR` (or runs it again when the
# kill came before the first checkpoint), and compares the resumed outputs
# with an uninterrupted run of the same frames, byte for byte. Prints a
# Markdown table (doc/reliability.md). Part of the test suite (ctest, label
# kill); exits non-zero on any difference.
#
# With --continue PREV, every run continues the finished run in PREV
# (avm-map --continue): a continued run killed at any instant resumes too.
#
# Usage: scripts/kill-test.sh --rawlog FILE [--continue PREV] [--model FILE] [--bin DIR]
#                             [--work DIR] [--kills N] [--seed S] [--frames N] [--interval S]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bin=$root/build/bin
rawlog=$root/datasets/bonn_crowd_sub300.rawlog
model=$root/datasets/yolox_nano.onnx
work=$root/output/kill-test
kills=4 seed=15 frames=200 interval=1 previous=

while [ $# -gt 0 ]; do
  case $1 in
    --rawlog) rawlog=$2; shift 2 ;;
    --continue) previous=$2; shift 2 ;;
    --model) model=$2; shift 2 ;;
    --bin) bin=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --kills) kills=$2; shift 2 ;;
    --seed) seed=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --interval) interval=$2; shift 2 ;;
    *) echo "kill-test: unknown argument $1 (see the header of $0)" >&2; exit 2 ;;
  esac
done
for f in "$rawlog" "$model" "$bin/avm-map"; do
  [ -e "$f" ] || { echo "kill-test: $f: not found" >&2; exit 2; }
done

rm -rf "$work"
mkdir -p "$work"
run=("$bin/avm-map" -q -c "$root/ini/default.ini" -r "$rawlog"
     --set "pipeline:checkpoint_interval_s=$interval" --set "pipeline:max_frames=$frames"
     --set pipeline:picture_size=0 --set "detection:model=$model")
[ -z "$previous" ] || run+=(--continue "$previous")
compared=(trajectory.txt detections.txt persons.csv map_low.bt map_high.bt keyframes.simplemap)

# The uninterrupted run: the reference, and how long a run takes.
start=$(date +%s.%N)
"${run[@]}" -o "$work/uninterrupted" > "$work/uninterrupted.out"
end=$(date +%s.%N)
total=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.2f", b - a }')
# Time before the first frame (loading the detector) and frames a second.
read -r runSeconds fps <<< "$(sed -n 's/.*"seconds": \([0-9.]*\).*/\1/p; s/.*"fps": \([0-9.]*\).*/\1/p' \
  "$work/uninterrupted/stats.json" | head -2 | tr '\n' ' ')"
startup=$(awk -v t="$total" -v r="$runSeconds" 'BEGIN { printf "%.2f", t - r }')

echo "| kill | instant [s] | resumed after frame | outputs equal |"
echo "|---|---|---|---|"
RANDOM=$seed
failures=0
for k in $(seq 1 "$kills"); do
  dir=$work/killed-$k
  # An instant between 5 % and 95 % of the run, in ms.
  instantMs=$(awk -v t="$total" -v r="$RANDOM" 'BEGIN { printf "%d", t * 1000 * (0.05 + 0.9 * r / 32767) }')
  instant=$(awk -v ms="$instantMs" 'BEGIN { printf "%.2f", ms / 1000 }')
  "${run[@]}" -o "$dir" > /dev/null 2>&1 &
  pid=$!
  sleep "$instant"
  kill -9 "$pid" 2> /dev/null || true
  wait "$pid" 2> /dev/null || true

  # Nothing, or a checkpoint (with the temporary of one being written, or
  # outputs, each whole, when the kill came while they were written), or the
  # finished run's outputs (a finished run removes its checkpoint after its
  # last output, avm-map.log).
  if [ -n "$(ls -A "$dir" 2> /dev/null)" ] && [ ! -f "$dir/checkpoint.bin" ] && [ ! -f "$dir/avm-map.log" ]; then
    echo "kill-test: kill $k at $instant s left files but no checkpoint: $(ls -A "$dir")" >&2
    failures=$((failures + 1))
    continue
  fi
  if [ -f "$dir/checkpoint.bin" ]; then
    cp "$dir/checkpoint.bin" "$dir.checkpoint-at-kill.bin"  # the resumed run writes its own
    "$bin/avm-map" -q --resume "$dir" > "$dir.out"
    after=$(sed -n 's/^resumed: *after frame \([0-9]*\).*/\1/p' "$dir.out")
    after=${after:-"none (the checkpoint before the first frame)"}
  elif [ -f "$dir/avm-map.log" ]; then
    after="none (finished before the kill)"
  else
    # Killed before the first checkpoint: the run starts over.
    "${run[@]}" -o "$dir" > "$dir.out"
    after="none (run again)"
  fi
  equal=yes
  for f in "${compared[@]}"; do
    if ! cmp -s "$work/uninterrupted/$f" "$dir/$f"; then
      equal="no ($f differs)"
      failures=$((failures + 1))
      break
    fi
  done
  echo "| $k | $instant | $after | $equal |"
done
# What the checkpoints cost the uninterrupted run (stats.json stages.checkpoint).
read -r ckMean ckCount <<< "$(awk '/"checkpoint": \{/ { on = 1 } on && /"mean_ms"/ { gsub(/[,"a-z_: ]/, ""); m = $0 }
  on && /"count"/ { gsub(/[,"a-z_: ]/, ""); print m, $0; exit }' "$work/uninterrupted/stats.json")"
share=$(awk -v m="$ckMean" -v c="$ckCount" -v s="$runSeconds" 'BEGIN { printf "%.2f", 100 * m * c / 1000 / s }')
echo
echo "Uninterrupted: $frames frames in ${total} s (${startup} s before the first frame, ${fps} fps), checkpoint every ${interval} s:" \
  "$ckCount checkpoints of ${ckMean} ms on average, ${share} % of the run time."
[ "$failures" -eq 0 ] || { echo "kill-test: $failures failure(s)" >&2; exit 1; }
