#!/usr/bin/env bash
# Re-runs the paper's evaluation (Table 1 voxel counts, Table 2 map size against
# the high-resolution share) on bonn_crowd_sub300, with ground-truth and with
# odometry poses, and writes doc/results.md and doc/results/*.png.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${AVM_BUILD_DIR:-$root/build}

source "$root/scripts/prepare.sh"
avm_prepare "$build" -DCMAKE_BUILD_TYPE=Release avm-paper
"$build/bin/avm-paper" --rawlog "$rawlog" --work "$root/output/paper" --results "$root/doc/results.md" "$@"
