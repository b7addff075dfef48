#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite under ctest,
# then again built with AddressSanitizer + UndefinedBehaviorSanitizer.
# Exits non-zero on any failure or sanitizer report.
# Usage: scripts/test.sh [ctest args...]    AVM_SKIP_SANITIZERS=1 skips the second pass.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${AVM_BUILD_DIR:-$root/build}
jobs=${AVM_JOBS:-$(nproc)}

"$root/scripts/install-deps.sh"

echo "== Release build and tests ($build)"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DAVM_BUILD_TESTS=ON >/dev/null
cmake --build "$build" -j "$jobs"
ctest --test-dir "$build" --output-on-failure -j "$jobs" "$@"

[ "${AVM_SKIP_SANITIZERS:-0}" = 1 ] && exit 0
# Stock MRPT binaries cannot preload an instrumented plugin: tests labelled
# stock-app run in the release pass only.
echo "== AddressSanitizer + UndefinedBehaviorSanitizer build and tests ($build-asan)"
cmake -S "$root" -B "$build-asan" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DAVM_SANITIZE=ON -DAVM_BUILD_TESTS=ON >/dev/null
cmake --build "$build-asan" -j "$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:halt_on_error=1 \
UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir "$build-asan" --output-on-failure -j "$jobs" -LE stock-app "$@"
