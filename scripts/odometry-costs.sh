#!/usr/bin/env bash
# What the odometry's cost settings buy and what they cost in accuracy: the
# default against variants that each turn one [odometry] key towards less
# work (fewer features, refinement rounds, pyramid levels, PnP RANSAC
# iterations or keyframes in the window bundle adjustment; a higher FAST
# threshold). For each, the CPU a frame of avm-map on the first
# core on the whole rgbd_bonn_crowd (else bonn_crowd_sub300): all threads, and
# the odometry's own thread; the median of five runs made alternately
# across the variants, as this virtual machine's speed moves from minute to
# minute. Then the ATE of each on the six sequences of
# scripts/odometry-sequences.sh --pipeline: one sequence's ATE moves by tens
# of percent with any change to the odometry (doc/odometry.md), six say more.
# Writes doc/odometry-costs.md with the commands and the machine.
# Usage: scripts/odometry-costs.sh
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${AVM_BUILD_DIR:-$root/build}
doc=$root/doc/odometry-costs.md
out=output/odometry-costs  # relative to the root, as the printed commands are

source "$root/scripts/prepare.sh"
avm_prepare "$build" -DCMAKE_BUILD_TYPE=Release avm-map avm-eval
madeBy=$(avm_made_by)  # before the runs: their machine and its load
rawlog=datasets/bonn_crowd_sub300.rawlog
if whole=$(avm_whole_sequence "$build"); then rawlog=${whole#"$root/"}; fi
bin=${build#"$root/"}/bin

cd "$root"
rm -rf "$out" && mkdir -p "$out"
# Each variant: its name and the one key it sets, section:key=value. The
# variants' inis hold that key alone (the built-in defaults are
# ini/default.ini's), so that each row differs from the default by one key.
variants=(features-700 odometry:num_features=700 features-500 odometry:num_features=500
  refine-rounds-2 odometry:refine_rounds=2 pyramid-levels-3 odometry:pyramid_levels=3
  fast-threshold-20 odometry:fast_threshold=20 ransac-iterations-50 odometry:ransac_iterations=50
  window-size-8 odometry:window_size=8)
inis=(ini/default.ini) names=(default) keys=("")
for ((i = 0; i < ${#variants[@]}; i += 2)); do
  name=${variants[i]} setting=${variants[i + 1]}
  section=${setting%%:*} assignment=${setting#*:}
  printf '[%s]\n%s = %s\n\n[map]\nadaptiveOctoMap_count = 1\n' "$section" "${assignment%%=*}" "${assignment#*=}" \
    >"$out/$name.ini"
  inis+=("$out/$name.ini") names+=("$name") keys+=("\`$section:$assignment\`")
done

commands=()
for repeat in 1 2 3 4 5; do
  for i in "${!inis[@]}"; do
    cmd=(taskset -c 0 "$bin/avm-map" -q -c "${inis[i]}" -r "$rawlog" -o "$out/${names[i]}-$repeat")
    [ "$repeat" != 1 ] || commands+=("${cmd[*]}  # and -2 to -5, each after every variant's run before")
    "${cmd[@]}" >/dev/null
  done
done
for i in "${!inis[@]}"; do
  for f in trajectory.txt map_low.bt map_high.bt; do
    for repeat in 2 3 4 5; do
      cmp -s "$out/${names[i]}-1/$f" "$out/${names[i]}-$repeat/$f" ||
        { echo "odometry-costs: $out/${names[i]}-$repeat/$f differs from the first run's" >&2; exit 1; }
    done
  done
done

# row I: variant I's row; CPU times the medians of its five runs. A variant
# that gives the default's trajectory (a key that changes nothing on these
# frames) says so: its CPU beside the default's is the measurement's spread.
row() {
  local run=$out/${names[$1]} cpu odometry same=
  cpu=$(for r in 1 2 3 4 5; do avm_stat "$run-$r" cpu_ms_per_frame; done | avm_median)
  odometry=$(for r in 1 2 3 4 5; do avm_stat "$run-$r" mean_ms odometry_cpu; done | avm_median)
  if [ "$1" != 0 ] && cmp -s "$out/default-1/trajectory.txt" "$run-1/trajectory.txt"; then
    same=" (the default's trajectory)"
  fi
  awk -v n="${names[$1]}" -v k="${keys[$1]:--}" -v c="$cpu" -v o="$odometry" \
    -v ate="$(avm_stat "$run-1" odometry_ate_rmse_m)" -v same="$same" \
    'BEGIN { printf "| %s | %s | %.1f | %.1f | %.4f%s |\n", n, k, c, o, ate, same }'
}
rows=()
for i in "${!inis[@]}"; do rows+=("$(row "$i")"); done
sequences=$("$root/scripts/odometry-sequences.sh" --pipeline "${inis[@]}")

tmp=$(mktemp "$root/doc/.odometry-costs.XXXX")
{
  echo "# What the odometry's cost settings buy"
  echo
  echo "$madeBy"
  echo
  echo "Each variant is \`ini/default.ini\` with one \`[odometry]\` key turned towards less work. All of avm-map on the first core, on \`$rawlog\`; CPU a frame over all threads and on the odometry's own thread (\`stages.odometry_cpu\`), each the median of five runs made alternately across the variants (the script checks that each variant's five trajectories and maps are the same bytes). A variant that gives the default's trajectory, byte for byte, is marked so: its CPU beside the default's is how far equal work measures apart on this virtual machine, whose speed moves from minute to minute. The odometry's CPU target of a small computer's core: at most 7 ms a frame, the whole run at most 16 ms (doc/performance.md)."
  echo
  echo "| variant | key | CPU, all threads [ms a frame] | odometry CPU [ms a frame] | ATE RMSE [m] |"
  echo "|---|---|---:|---:|---:|"
  printf '%s\n' "${rows[@]}"
  echo
  echo "\`\`\`"
  printf '%s\n' "${commands[@]}"
  echo "\`\`\`"
  echo
  echo "## The ATE on six sequences"
  echo
  echo "\`scripts/odometry-sequences.sh --pipeline\` (doc/odometry.md): each variant on bonn_crowd_sub300, four sequences made from it and the whole sequence."
  echo
  echo "$sequences"
} >"$tmp"
mv "$tmp" "$doc"
cat "$doc"
