#!/usr/bin/env bash
# The long run under AddressSanitizer + LeakSanitizer: bonn_crowd_sub300
# replayed 10 times in one avm-map process (3000 frames, frame indices and
# timestamps continued, ground-truth poses, detection every third frame, region
# map), built as in the sanitizer pass of scripts/test.sh. Any leak or error
# report fails it; prints the peak memory after each replay.
# Usage: scripts/long-run.sh [REPLAYS]   (default 10)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${AVM_BUILD_DIR:-$root/build}-asan
replays=${1:-10}
out=$root/output/long-run-asan

source "$root/scripts/prepare.sh"
avm_prepare "$build" "-DCMAKE_BUILD_TYPE=RelWithDebInfo -DAVM_SANITIZE=ON" avm-map

cd "$root"
cmd=("$build/bin/avm-map" -q -c ini/default.ini -r datasets/bonn_crowd_sub300.rawlog -o "$out" --poses gt
     --set "pipeline:repeat=$replays")
echo "${cmd[*]}"
ASAN_OPTIONS=detect_leaks=1:halt_on_error=1:intercept_tls_get_addr=0 \
UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:suppressions=$root/tests/sanitizers/ubsan.supp \
  "${cmd[@]}"
echo "exit status 0: no AddressSanitizer, LeakSanitizer or UndefinedBehaviorSanitizer report"
echo "peak memory per replay [MiB]: $(tr -d '\n ' < "$out/stats.json" | sed -E 's/.*"peak_memory_mb_per_replay":\[([^]]*)\].*/\1/')"
