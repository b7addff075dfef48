# shellcheck shell=bash
# Sourced by the scripts that run avm on the default dataset:
#   avm_prepare BUILD_DIR "CMAKE_OPTIONS" [TARGET...]
# installs what is missing, configures and builds BUILD_DIR (all targets when
# none are named), fills datasets/ (scripts/get-data.sh) and converts the
# default dataset to datasets/bonn_crowd_sub300.rawlog once. Sets $rawlog.
# The rawlog holds the frames as a camera gives them (colour inside, no gzip:
# ~460 MB): replaying it decodes nothing, where PNG colour and gzip cost ~15 ms
# of CPU a frame, half a frame period at 30 Hz (doc/performance.md).
# Below it, what the measuring scripts share: the whole sequence's rawlog
# (avm_whole_sequence), a number of a run's stats.json (avm_stat), a median
# (avm_median), a doc's first line naming the machine (avm_made_by).
avm_prepare() {
  local build=$1 options=$2
  shift 2
  local root
  root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
  "$root/scripts/install-deps.sh"
  # shellcheck disable=SC2086  # the options are words
  cmake -S "$root" -B "$build" $options >/dev/null
  local targets=()
  for t in "$@"; do targets+=(--target "$t"); done
  [ $# -eq 0 ] || targets+=(--target avm-tum2rawlog)
  cmake --build "$build" -j "$(nproc)" "${targets[@]}"
  "$root/scripts/get-data.sh"
  rawlog=$root/datasets/bonn_crowd_sub300.rawlog
  # A gzip rawlog is the form earlier versions made: converted again.
  if [ ! -f "$rawlog" ] || [ "$(head -c2 "$rawlog" | od -An -tx1 | tr -d ' ')" = 1f8b ]; then
    rm -rf "${rawlog%.rawlog}_Images"
    "$build/bin/avm-tum2rawlog" --camera bonn --gt-body bonn --embed-images --compression 0 \
      "$root/datasets/bonn_crowd_sub300" "$rawlog"
  fi
}

# avm_whole_sequence BUILD_DIR: where the whole rgbd_bonn_crowd is in datasets/
# (scripts/get-data.sh --whole-sequence), makes datasets/rgbd_bonn_crowd.rawlog
# from it once (its first frame is before the ground truth starts: trimmed)
# and prints that path; fails where the sequence is not there.
avm_whole_sequence() {
  local build=$1 root whole
  root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
  whole=$root/datasets/rgbd_bonn_crowd
  if [ -f "$whole/rgb.txt" ] && [ ! -f "$whole.rawlog" ]; then
    "$build/bin/avm-tum2rawlog" -q --camera bonn --gt-body bonn --embed-images --compression 0 \
      --trim-to-ground-truth "$whole" "$whole.rawlog" >&2
  fi
  [ -f "$whole.rawlog" ] && echo "$whole.rawlog"
}

# avm_required_whole_sequence BUILD_DIR SCRIPT_NAME: avm_whole_sequence's rawlog,
# relative to the root, for a script that cannot run without it: where the
# sequence is not in datasets/, says so naming the script and fails.
avm_required_whole_sequence() {
  local root whole
  root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
  whole=$(avm_whole_sequence "$1") ||
    { echo "$2: the whole rgbd_bonn_crowd is not in datasets/ (scripts/get-data.sh --whole-sequence)" >&2; return 1; }
  echo "${whole#"$root/"}"
}

# avm_stat RUN_DIR KEY [OBJECT]: the first number named KEY in RUN_DIR/stats.json
# (within the object named OBJECT, one without nested objects, when given).
avm_stat() {
  local json
  json=$(tr -d '\n ' <"$1/stats.json")
  [ $# -lt 3 ] || json=$(sed -nE "s/.*\"$3\":\{([^}]*)\}.*/\1/p" <<<"$json")
  sed -nE "s/.*\"$2\":([-0-9.eE+]+).*/\1/p" <<<"$json" | head -1
}

# avm_median: the median of the numbers on stdin, one a line (an odd count).
avm_median() {
  local values
  mapfile -t values < <(sort -g)
  echo "${values[$((${#values[@]} / 2))]}"
}

# avm_made_by: a doc's first line, "Made by `scripts/SCRIPT` on DATE:
# MACHINE, load average ...", SCRIPT the one running: called before the runs,
# whose load it reports.
avm_made_by() {
  echo "Made by \`scripts/$(basename "$0")\` on $(date -u '+%Y-%m-%d %H:%M UTC'): $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores, load average before the runs $(cut -d' ' -f1-3 /proc/loadavg). Release build."
}
