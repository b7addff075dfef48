#!/usr/bin/env bash
# Re-runs the paper's evaluation (Table 1 voxel counts, Table 2 map size against
# the high-resolution share of the run, avm's per-person regions against single
# OctoMaps), with ground-truth and with odometry poses, and writes a results
# file, whole, with its pictures in doc/results/*.png. The datasets:
#   bonn_crowd_sub300   the default dataset: doc/results.md
#   rgbd_bonn_crowd     the whole sequence (scripts/get-data.sh --whole-sequence):
#                       doc/results-whole.md
# Without a dataset named, both where they are in datasets/. Each writes only
# its own file. Options after -- go to avm-paper.
# Usage: scripts/reproduce-paper.sh [DATASET...] [-- AVM-PAPER-OPTIONS...]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${AVM_BUILD_DIR:-$root/build}
datasets=()
while [ $# -gt 0 ] && [ "$1" != -- ]; do datasets+=("$1"); shift; done
[ $# -eq 0 ] || shift

source "$root/scripts/prepare.sh"
avm_prepare "$build" -DCMAKE_BUILD_TYPE=Release avm-paper
whole=$(avm_whole_sequence "$build") || whole=
if [ ${#datasets[@]} -eq 0 ]; then
  datasets=(bonn_crowd_sub300)
  [ -z "$whole" ] || datasets+=(rgbd_bonn_crowd)
fi

for d in "${datasets[@]}"; do
  case $d in
    bonn_crowd_sub300)
      "$build/bin/avm-paper" --rawlog "$rawlog" --work "$root/output/paper" --results "$root/doc/results.md" "$@" ;;
    rgbd_bonn_crowd)
      [ -n "$whole" ] || { echo "reproduce-paper.sh: datasets/rgbd_bonn_crowd is not there (scripts/get-data.sh --whole-sequence)" >&2; exit 1; }
      "$build/bin/avm-paper" --rawlog "$whole" --work "$root/output/paper-whole" --results "$root/doc/results-whole.md" "$@" ;;
    *) echo "reproduce-paper.sh: unknown dataset '$d' (bonn_crowd_sub300 or rgbd_bonn_crowd)" >&2; exit 1 ;;
  esac
done
