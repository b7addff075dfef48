#!/usr/bin/env bash
# Runs every libFuzzer target for SECONDS each (default 60), starting from the
# seed corpus in tests/fuzz/corpus/<target>/. Builds with clang, ASan and UBSan
# in build-fuzz/. A crash stops with the reproducer's path: add it to
# tests/fuzz/regressions/<target>/ so the replay tests keep it fixed.
# Out-of-memory inputs are counted, not failures: MRPT 2.5.8 sizes vectors
# from the file before reading them, so a corrupt rawlog can allocate GBs
# before it fails (doc/reliability.md); fork mode fuzzes on past them.
# Usage: scripts/fuzz.sh [SECONDS] [TARGET...]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
seconds=${1:-60}
shift || true
build=$root/build-fuzz

"$root/scripts/install-deps.sh"
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DAVM_FUZZ=ON -DAVM_BUILD_TESTS=ON >/dev/null
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  mapfile -t targets < <(cd "$root/tests/fuzz" && ls fuzz_*.cpp | sed -E 's/^fuzz_(.*)\.cpp$/\1/')
fi
cmake --build "$build" -j "$(nproc)" --target "${targets[@]/#/fuzz-}"

status=0
for t in "${targets[@]}"; do
  work=$build/corpus/$t artifacts=$build/artifacts/$t/
  mkdir -p "$work" "$artifacts"
  cp -n "$root/tests/fuzz/corpus/$t/"* "$work/" 2>/dev/null || true
  echo "fuzz: $t for ${seconds}s"
  ASAN_OPTIONS=detect_leaks=1:intercept_tls_get_addr=0 "$build/bin/fuzz-$t" "$work" -max_total_time="$seconds" -fork=1 \
    -ignore_ooms=1 -timeout=20 -rss_limit_mb=4096 -artifact_prefix="$artifacts" \
    > "$build/fuzz-$t.log" 2>&1 || true
  # Fork mode's last status line: "#EXECS: cov: .. corp: N .. oom/timeout/crash: O/T/C ..."
  last=$(grep -E '^#[0-9]+: cov:' "$build/fuzz-$t.log" | tail -n1 || true)
  execs=$(sed -E 's/^#([0-9]+):.*/\1/' <<<"$last")
  read -r ooms timeouts crashes < <(sed -E 's#.*oom/timeout/crash: ([0-9]+)/([0-9]+)/([0-9]+).*#\1 \2 \3#' <<<"$last")
  leaks=$(grep -c 'ERROR: LeakSanitizer' "$build/fuzz-$t.log" || true)
  failures=$(( ${timeouts:-0} + ${crashes:-0} + leaks ))
  echo "fuzz: $t: ${execs:-0} inputs run, corpus $(ls "$work" | wc -l), out-of-memory ${ooms:-0}, timeouts ${timeouts:-0}, crashes ${crashes:-0}, leaks $leaks"
  if [ "$failures" -gt 0 ]; then
    echo "fuzz: $t FAILED, reproducers in $artifacts (log: $build/fuzz-$t.log)" >&2
    status=1
  fi
done
exit $status
