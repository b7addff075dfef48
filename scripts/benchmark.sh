#!/usr/bin/env bash
# End-to-end benchmark of avm-map on the default dataset (odometry + detection
# + map, all 300 frames at 640x480, ini/default.ini, five times: the first
# printed, all five in the closing tables), each speed setting of the default
# against its alternative (detector input, read-ahead, mapping thread, a gzip
# rawlog with PNG colour, detection on every frame; a table), and a long run
# (the sequence replayed 10 times, 3000 frames, ground-truth poses), with the live view
# (--gui under xvfb-run: speed and peak memory against none, and the peak on
# the whole sequence when it is there), written to
# doc/performance.md with the commands and the machine. Where the whole
# rgbd_bonn_crowd is in datasets/ (scripts/get-data.sh --whole-sequence), also
# avm-map on it on one core (taskset -c 0), twice, and whether the two
# trajectories are the same bytes (a table). avm-map's log lines (loops, lost
# frames) are left out of the runs printed; each run's avm-map.log has them.
# Then the CPU a frame by stage (odometry, detector, map, the rest) on one core
# and on two, the map stage against octomap's insertion in the same run, and
# the odometry's own stages (avm-odometry --stage-times, one core). Last,
# ini/small-computer.ini against the default: CPU a frame by stage on one
# core, the map against octomap's, and the ATE on six sequences
# (scripts/odometry-sequences.sh --pipeline).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${AVM_BUILD_DIR:-$root/build}
out=$root/output/benchmark
doc=$root/doc/performance.md

source "$root/scripts/prepare.sh"
avm_prepare "$build" -DCMAKE_BUILD_TYPE=Release avm-map avm-odometry

defaults=(default default-2 default-3 default-4 default-5)

map_command() {  # map_command NAME [--rawlog FILE] [--ini FILE] ARGS... : sets cmd, the avm-map command of run NAME
  local name=$1 input=datasets/bonn_crowd_sub300.rawlog ini=ini/default.ini; shift
  if [ "${1:-}" = --rawlog ]; then input=$2; shift 2; fi
  if [ "${1:-}" = --ini ]; then ini=$2; shift 2; fi
  cmd=(build/bin/avm-map -q -c "$ini" -r "$input" -o "output/benchmark/$name" "$@")
}
one_core_run() {  # one_core_run NAME ARGS... : map_command's run on the first core, its command printed
  map_command "$@"
  cmd=(taskset -c 0 "${cmd[@]}")
  echo "${cmd[*]}"
  (cd "$root" && "${cmd[@]}" >/dev/null)
}

run() {  # run NAME [--rawlog FILE] ARGS... : prints the command and avm-map's summary
  map_command "$@"
  echo "\`\`\`"
  echo "${cmd[*]}"
  (cd "$root" && "${cmd[@]}" | grep -vE '^ done\.$|^outputs in|^\[[0-9:.]+\|(INFO |WARN )\|')
  echo "\`\`\`"
}

quiet_run() {  # quiet_run NAME [--rawlog FILE] ARGS... : a run whose stats.json is all that is kept
  map_command "$@"
  (cd "$root" && "${cmd[@]}" >/dev/null)
}

pair_field() {  # pair_field WITH WITHOUT KEY DECIMALS : "with / without" from two runs' stats.json
  printf "%.${4}f / %.${4}f" "$(field "$1" "$3")" "$(field "$2" "$3")"
}

field() {  # field RUN KEY : a top-level number from the run's stats.json, or n/a
  tr -d '\n ' < "$out/$1/stats.json" | sed -nE "s/.*\"$2\":([-0-9.eE+]+).*/\1/p" | grep . || echo n/a
}
stage() {  # stage RUN NAME : mean_ms of one stage
  tr -d '\n ' < "$out/$1/stats.json" | sed -E "s/.*\"$2\":\{\"mean_ms\":([-0-9.eE+]+).*/\1/" | awk '{printf "%.1f", $1}'
}
value_in() {  # value_in RUN OBJECT KEY : one number of a stats.json object (a stage's mean_ms, count ...)
  tr -d '\n ' < "$out/$1/stats.json" | sed -nE "s/.*\"$2\":\{[^}]*\"$3\":([-0-9.eE+]+).*/\1/p"
}
cpu_row() {  # cpu_row RUN CORES : a row of the table of CPU a frame by stage
  awk -v r="$1" -v c="$2" -v fps="$(field "$1" fps)" -v f="$(field "$1" frames)" -v t="$(field "$1" cpu_ms_per_frame)" \
    -v o="$(value_in "$1" odometry_cpu mean_ms)" -v dm="$(value_in "$1" detection_cpu mean_ms)" \
    -v dn="$(value_in "$1" detection_cpu count)" -v m="$(value_in "$1" map_cpu mean_ms)" \
    -v ate="$(field "$1" odometry_ate_rmse_m)" 'BEGIN {
      d = dm * dn / f
      printf "| %s | %s | %.1f | %.1f | %.1f | %.1f (%.1f a run) | %.1f | %.1f | %.4f |\n", r, c, fps, t, o, d, dm, m, t - o - d - m, ate
    }'
}
octomap_cells() {  # octomap_cells RUN : "map stage | octomap's insertion | ratio" of a run with reference maps
  echo "$(stage "$1" map_cpu) | $(value_in "$1" single_high insert_mean_ms | awk '{printf "%.1f", $1}') | $(field "$1" map_cpu_speedup_vs_single_high | awk '{printf "%.1fx", $1}')"
}
checkpoints() {  # checkpoints RUN : "N x M ms (P % of the run)" from stages.checkpoint and seconds
  tr -d '\n ' < "$out/$1/stats.json" |
    sed -nE 's/.*"seconds":([-0-9.eE+]+).*"checkpoint":\{"mean_ms":([-0-9.eE+]+),[^}]*"count":([0-9]+)\}.*/\1 \2 \3/p' |
    awk '{printf "%d x %.1f ms (%.2f %%)", $3, $2, 100 * $2 * $3 / 1000 / $1}'
}

mkdir -p "$out"
[ -f "$out/bonn_crowd_sub300_gz.rawlog" ] ||
  "$build/bin/avm-tum2rawlog" -q --camera bonn --gt-body bonn "$root/datasets/bonn_crowd_sub300" "$out/bonn_crowd_sub300_gz.rawlog" >/dev/null

tmp=$(mktemp "$root/doc/.performance.XXXX")
{
  echo "# End-to-end performance"
  echo
  echo "Made by \`scripts/benchmark.sh\` on $(date -u '+%Y-%m-%d %H:%M UTC'): $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //') (cpu family $(grep -m1 'cpu family' /proc/cpuinfo | cut -d: -f2 | tr -d ' '), model $(grep -m1 '^model[[:space:]]*:' /proc/cpuinfo | cut -d: -f2 | tr -d ' '): virtual machines that print the same name can differ in speed), $(nproc) cores, $(free -g | awk '/Mem:/{print $2}') GiB, load average before the runs $(cut -d' ' -f1-3 /proc/loadavg)."
  echo "Release build. Every figure below is printed by the command above it (also in \`output/benchmark/*/stats.json\`); avm-map's log lines are left out (each run's \`avm-map.log\` has them)."
  echo
  echo "## The default run: odometry + detection every third frame on a worker thread + region map"
  echo
  echo "Targets: at least 30 frames per second over all 300 frames (real-time factor >= 1 for this 30 Hz camera), peak memory below 1 GB."
  echo
  echo "Five runs of the same command, to show the spread: the first as avm-map prints it, all five in the tables of \"Against the targets\" below. The machine is a virtual machine whose speed moves from minute to minute: each run measures the CPU time it used a frame (all threads) and the share of the machine's CPU time the hypervisor gave to other guests meanwhile (steal)."
  echo
  run "${defaults[0]}"
  for r in "${defaults[@]:1}"; do quiet_run "$r"; done
  echo
  echo "## What the default's speed settings buy"
  echo
  echo "The default detects at 256x192 (the 640x480 frame scaled by 0.4, no padding), reads frames ahead on a thread of its own, inserts a frame into the map on a worker thread while odometry processes the next, and replays a rawlog that holds the frames as a camera gives them (\`avm-tum2rawlog --embed-images --compression 0\`). Against: YOLOX-Nano's native 416x416 input; 320x256; reading on the main loop's thread; inserting on it; the gzip rawlog with the colour as PNG files (the converter's default form); and detection on every frame, synchronous (the slowest setting):"
  echo
  echo "\`\`\`"
  settings=(input-416 input-320x256 no-read-ahead no-mapping-thread gzip-png-rawlog every-frame)
  quiet_run input-416 --set detection:input_width=416 --set detection:input_height=416 && echo "${cmd[*]}"
  quiet_run input-320x256 --set detection:input_width=320 --set detection:input_height=256 && echo "${cmd[*]}"
  quiet_run no-read-ahead --set pipeline:read_ahead_frames=0 && echo "${cmd[*]}"
  quiet_run no-mapping-thread --set pipeline:async_mapping=false && echo "${cmd[*]}"
  quiet_run gzip-png-rawlog --rawlog output/benchmark/bonn_crowd_sub300_gz.rawlog && echo "${cmd[*]}"
  quiet_run every-frame --set pipeline:detect_every_n=1 --set pipeline:async_detection=false && echo "${cmd[*]}"
  echo "\`\`\`"
  echo
  echo "| run | fps | CPU [ms a frame, all threads] | peak memory [MiB] | odometry [ms] | detection [ms a run] | map [ms] | odometry ATE RMSE [m] |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|"
  for r in "${defaults[0]}" "${settings[@]}"; do
    echo "| $r | $(field "$r" fps | awk '{printf "%.1f", $1}') | $(field "$r" cpu_ms_per_frame | awk '{printf "%.1f", $1}') | $(field "$r" peak_memory_mb | awk '{printf "%.0f", $1}') | $(stage "$r" odometry) | $(stage "$r" detection) | $(stage "$r" map) | $(field "$r" odometry_ate_rmse_m | awk '{printf "%.4f", $1}') |"
  done
  echo
  echo "## The live view (--gui), alternating runs"
  echo
  echo "Three pairs under a virtual X server (\`xvfb-run -a\`, Mesa's software OpenGL draws the view), each the default with \`--gui\` (\`gui_fps = 5\`) and then without, so that both see the machine in the same mood:"
  echo
  echo "| pair | fps with / without | CPU [ms a frame] with / without | map stage [ms] with / without | CPU time stolen [%] with / without | peak memory [MiB] with / without |"
  echo "|---|---:|---:|---:|---:|---:|"
  for i in 1 2 3; do
    map_command "gui-$i" --gui --gui-no-wait  # a scripted run: no wait for the user at the end
    (cd "$root" && xvfb-run -a "${cmd[@]}" >/dev/null)
    quiet_run "no-gui-$i"
    echo "| $i | $(pair_field "gui-$i" "no-gui-$i" fps 1) | $(pair_field "gui-$i" "no-gui-$i" cpu_ms_per_frame 1) | $(printf "%.1f / %.1f" "$(stage "gui-$i" map)" "$(stage "no-gui-$i" map)") | $(pair_field "gui-$i" "no-gui-$i" cpu_stolen_percent 0) | $(pair_field "gui-$i" "no-gui-$i" peak_memory_mb 0) |"
  done
  echo
  if [ -f "$root/datasets/rgbd_bonn_crowd.rawlog" ]; then
    # The view's memory must not grow with the run: the whole
    # sequence, three times sub300's frames, with the view.
    map_command gui-whole --rawlog datasets/rgbd_bonn_crowd.rawlog --gui --gui-no-wait
    (cd "$root" && xvfb-run -a "${cmd[@]}" >/dev/null)
    echo "The whole \`rgbd_bonn_crowd\` (926 frames) with the view, \`xvfb-run -a ${cmd[*]}\`: peak memory $(field gui-whole peak_memory_mb | awk '{printf "%.0f", $1}') MiB, $(field gui-whole fps | awk '{printf "%.1f", $1}') fps."
    echo
  fi
  echo "The view draws on its own thread; the loop only takes a snapshot of the map when one is due (at most \`gui_fps\` a second, between two insertions): doc/viewer.md has its measured cost."
  echo
  if [ -f "$root/datasets/rgbd_bonn_crowd/rgb.txt" ]; then
    [ -f "$root/datasets/rgbd_bonn_crowd.rawlog" ] ||
      "$build/bin/avm-tum2rawlog" -q --camera bonn --gt-body bonn --embed-images --compression 0 --trim-to-ground-truth \
        "$root/datasets/rgbd_bonn_crowd" "$root/datasets/rgbd_bonn_crowd.rawlog" >/dev/null
    echo "## The whole sequence on one core"
    echo
    echo "All 926 frames of \`rgbd_bonn_crowd\` that the ground truth covers, every thread of avm-map on the first core (\`taskset -c 0\`), twice. Targets: at least 30 frames per second, odometry at most 20 ms a frame, and the two runs' trajectories the same bytes:"
    echo
    echo "\`\`\`"
    for i in 1 2; do one_core_run "whole-one-core-$i" --rawlog datasets/rgbd_bonn_crowd.rawlog; done
    echo "\`\`\`"
    echo
    echo "The odometry's wall clock on one core also counts the detection and map threads that take the core meanwhile; its CPU time on its own thread (\`stages.odometry_cpu\`) is what one thread of odometry costs."
    echo
    echo "| run | fps | odometry [ms a frame, wall] | odometry [ms a frame, CPU of its thread] | CPU [ms a frame, all threads] | odometry ATE RMSE [m] |"
    echo "|---|---:|---:|---:|---:|---:|"
    for i in 1 2; do
      r=whole-one-core-$i
      echo "| $r | $(field "$r" fps | awk '{printf "%.1f", $1}') | $(stage "$r" odometry) | $(stage "$r" odometry_cpu) | $(field "$r" cpu_ms_per_frame | awk '{printf "%.1f", $1}') | $(field "$r" odometry_ate_rmse_m | awk '{printf "%.4f", $1}') |"
    done
    echo
    if cmp -s "$out/whole-one-core-1/trajectory.txt" "$out/whole-one-core-2/trajectory.txt"; then
      echo "\`cmp output/benchmark/whole-one-core-1/trajectory.txt output/benchmark/whole-one-core-2/trajectory.txt\`: the same bytes."
    else
      echo "\`cmp output/benchmark/whole-one-core-1/trajectory.txt output/benchmark/whole-one-core-2/trajectory.txt\`: **the two trajectories differ**."
    fi
    echo
  fi
  echo "## Where a frame's CPU goes, on one core and on two"
  echo
  echo "\`ini/default.ini\`, every thread of avm-map on the first core (\`taskset -c 0\`) or on both. CPU time a frame by stage: the odometry on the loop's thread (\`stages.odometry_cpu\`), the detector on its thread (\`stages.detection_cpu\`: a run's CPU time times the runs, over the frames; it runs on every third frame), the map stage on its thread (\`stages.map_cpu\`), and the rest (reading frames, the loop's person and region bookkeeping, checkpoints, handing frames between threads): the run's CPU time less the three. \`whole-one-core-on-change\` runs the detector where the view changed instead of on every third frame (\`detection_schedule = on_change\`; its runs, the persons it finds and its ATE on six sequences: [detection-schedule.md](detection-schedule.md)); \`whole-one-core-exported-graph\` runs the detector's model with its graph as exported, without the rewrite of [detection.md](detection.md) (\`simplify_graph = false\`). Targets of a small computer's single core: at most 16 ms a frame (60 fps), the odometry at most 7 ms."
  echo
  echo "\`\`\`"
  cpu_runs=("${defaults[0]}:2" sub300-one-core:1)
  one_core_run sub300-one-core
  if [ -f "$root/datasets/rgbd_bonn_crowd.rawlog" ]; then
    quiet_run whole-two-cores --rawlog datasets/rgbd_bonn_crowd.rawlog && echo "${cmd[*]}"
    one_core_run whole-one-core-on-change --rawlog datasets/rgbd_bonn_crowd.rawlog --set pipeline:detection_schedule=on_change
    one_core_run whole-one-core-exported-graph --rawlog datasets/rgbd_bonn_crowd.rawlog --set detection:simplify_graph=false
    cpu_runs+=(whole-one-core-1:1 whole-two-cores:2 whole-one-core-on-change:1 whole-one-core-exported-graph:1)
  fi
  echo "\`\`\`"
  echo
  echo "(\`${defaults[0]}\` is the first default run above; \`whole-one-core-1\`, the first of the whole sequence on one core.)"
  echo
  echo "| run | cores | fps | CPU [ms a frame, all threads] | odometry [ms CPU a frame] | detection [ms CPU a frame] | map [ms CPU a frame] | the rest [ms] | odometry ATE RMSE [m] |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|"
  for rc in "${cpu_runs[@]}"; do cpu_row "${rc%:*}" "${rc#*:}"; done
  echo
  echo "The map stage against octomap's own insertion of the same frames into a single 0.05 m OctoMap in the same run (\`[pipeline] reference_maps = true\`: \`reference.map_cpu_speedup_vs_single_high\` of stats.json, the octomap insertion's CPU time over the map stage's; target at least 8x):"
  echo
  echo "\`\`\`"
  reference_runs=(sub300-reference)
  quiet_run sub300-reference --set pipeline:reference_maps=true && echo "${cmd[*]}"
  if [ -f "$root/datasets/rgbd_bonn_crowd.rawlog" ]; then
    quiet_run whole-reference --rawlog datasets/rgbd_bonn_crowd.rawlog --set pipeline:reference_maps=true && echo "${cmd[*]}"
    reference_runs+=(whole-reference)
  fi
  echo "\`\`\`"
  echo
  echo "| run | map stage [ms CPU a frame] | octomap 0.05 m insertion [ms a frame] | ratio |"
  echo "|---|---:|---:|---:|"
  for r in "${reference_runs[@]}"; do
    echo "| $r | $(octomap_cells "$r") |"
  done
  echo
  echo "Inside the odometry: \`avm-odometry\` alone on the first core, on the whole sequence where it is there (else sub300), with the detector on every frame between its stages. One thread: a stage's wall time is its CPU time. MRPT's CTimeLogger table of its stages (1.1 and 1.2 within 1: ORB's detection, that is the pyramid, FAST and the Harris score, and the orientation and description of the features the bucketing keeps; the rest of 1 is the person mask, the grid bucketing and the features' depth), and the odometry's own time a frame (all stages):"
  echo
  echo "\`\`\`"
  odometry_input=datasets/bonn_crowd_sub300.rawlog
  [ -f "$root/datasets/rgbd_bonn_crowd.rawlog" ] && odometry_input=datasets/rgbd_bonn_crowd.rawlog
  odometry_cmd=(taskset -c 0 build/bin/avm-odometry -c ini/default.ini --stage-times "$odometry_input" output/benchmark/odometry-stages.txt)
  echo "${odometry_cmd[*]}"
  (cd "$root" && "${odometry_cmd[@]}") | grep -vE '^-+ avm odometry stages|^loop|^  (measured|tracked) ?:' | sed -n '/^frames /,$p'
  echo "\`\`\`"
  echo
  echo "What each of the odometry's cost settings (features, refinement rounds, pyramid levels, the window ...) buys in CPU and costs in ATE on six sequences: [odometry-costs.md](odometry-costs.md) (\`scripts/odometry-costs.sh\`)."
  echo
  if [ -f "$root/datasets/rgbd_bonn_crowd.rawlog" ]; then
    small=ini/small-computer.ini
    echo "## A small computer's setting: \`$small\`"
    echo
    echo "The default above is the accurate setting. \`$small\` is for a board that must keep up at 60 frames a second on one core (at most 16 ms of CPU a frame): the odometry keeps 700 features on a 3-level pyramid (\`num_features\`, \`pyramid_levels\`; 1000 on 4 in the default) and the detector runs where the view changed (\`detection_schedule = on_change\`, [detection-schedule.md](detection-schedule.md) has its walk-ins). The map's settings are the default's. Runs of the whole sequence on the first core, the default and the setting in turn (the machine's speed moves from minute to minute), CPU a frame by stage as in the table above:"
    echo
    echo "\`\`\`"
    small_runs=()
    for i in 1 2; do
      one_core_run "whole-one-core-default-$i" --rawlog datasets/rgbd_bonn_crowd.rawlog
      one_core_run "whole-one-core-small-computer-$i" --rawlog datasets/rgbd_bonn_crowd.rawlog --ini "$small"
      small_runs+=("whole-one-core-default-$i" "whole-one-core-small-computer-$i")
    done
    one_core_run sub300-one-core-small-computer --ini "$small"
    echo "\`\`\`"
    echo
    echo "| run | cores | fps | CPU [ms a frame, all threads] | odometry [ms CPU a frame] | detection [ms CPU a frame] | map [ms CPU a frame] | the rest [ms] | odometry ATE RMSE [m] |"
    echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|"
    for r in sub300-one-core sub300-one-core-small-computer "${small_runs[@]}"; do cpu_row "$r" 1; done
    echo
    echo "The map it makes, against octomap's single maps of the same frames at its poses, as \`whole-reference\` above does for the default ([results.md](results.md) explains the references): memory against the single 0.05 m map, the IoU of the occupied voxels outside the regions (against the single 0.20 m map) and inside the regions active at the end (against the single 0.05 m map whose moving persons' pixels are free-only), and the map stage against octomap's insertion:"
    echo
    echo "\`\`\`"
    quiet_run whole-reference-small-computer --rawlog datasets/rgbd_bonn_crowd.rawlog --ini "$small" \
      --set pipeline:reference_maps=true && echo "${cmd[*]}"
    echo "\`\`\`"
    echo
    echo "| run | memory, share of the single 0.05 m map | IoU outside the regions | IoU inside (moving persons free-only) | map stage [ms CPU a frame] | octomap 0.05 m [ms a frame] | ratio |"
    echo "|---|---:|---:|---:|---:|---:|---:|"
    for r in whole-reference whole-reference-small-computer; do
      echo "| $r | $(field "$r" memory_share_of_single_high_all_pixels | awk '{printf "%.3f", $1}') | $(field "$r" outside_regions_iou | awk '{printf "%.3f", $1}') | $(field "$r" inside_regions_iou_vs_single_high_moving_free_only | awk '{printf "%.3f", $1}') | $(octomap_cells "$r") |"
    done
    echo
    echo "What it costs in pose accuracy, on six sequences (\`scripts/odometry-sequences.sh --pipeline\`, [odometry.md](odometry.md) says what each sequence is):"
    echo
    (cd "$root" && scripts/odometry-sequences.sh --pipeline ini/default.ini "$small")
    echo
  fi
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
  echo "| target | the five default runs |"
  echo "|---|---|"
  echo "| >= 30 frames per second, detection on at least every third frame | $(for r in "${defaults[@]}"; do field "$r" fps; done | awk '{printf "%s%.1f", (NR > 1 ? ", " : ""), $1; n+=($1>=30)} END {printf " fps: met in %d of %d", n, NR}') |"
  echo "| peak memory < 1 GB | $(for r in "${defaults[@]}"; do field "$r" peak_memory_mb; done | awk '{printf "%s%.0f", (NR > 1 ? ", " : ""), $1; n+=($1<1024)} END {printf " MiB: met in %d of %d", n, NR}') |"
  echo
  echo "| default run | fps | CPU [ms a frame, all threads] | CPU time stolen [%] | odometry [ms] | detection [ms a run] | map [ms] | checkpoints (share of the run) |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|"
  for r in "${defaults[@]}"; do
    echo "| $r | $(field "$r" fps | awk '{printf "%.1f", $1}') | $(field "$r" cpu_ms_per_frame | awk '{printf "%.1f", $1}') | $(field "$r" cpu_stolen_percent | awk '{printf "%.0f", $1}') | $(stage "$r" odometry) | $(stage "$r" detection) | $(stage "$r" map) | $(checkpoints "$r") |"
  done
  echo
  echo "Checkpoints: \`[pipeline] checkpoint_interval_s\` = 5 (the default), one before the first frame and one after the last; a checkpoint waits for the insertion in flight and writes the maps, trajectory, person records and odometry state (doc/reliability.md has the kill test)."

  echo
  echo "The stage times are wall-clock on a loaded machine (three busy threads on two cores); the CPU time a frame is the work, less sensitive to the machine's moods."
} > "$tmp"
mv "$tmp" "$doc"
cat "$doc"
