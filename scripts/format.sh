#!/usr/bin/env bash
# avm's C++ in the style of .clang-format (after MRPT's), with Debian
# bookworm's clang-format 14: other versions break lines differently.
#   scripts/format.sh           formats every .h and .cpp of app/, modules/, tests/ in place
#   scripts/format.sh --check   changes nothing; lists the files that are not formatted, exits 1 if any
# --check is part of the test suite (ctest test "clang-format").
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
tool=clang-format-14
command -v "$tool" >/dev/null || { echo "format: $tool not found (scripts/install-deps.sh installs it)" >&2; exit 2; }

mapfile -d '' files < <(cd "$root" && find app modules tests \( -name '*.h' -o -name '*.cpp' \) -print0 | sort -z)
cd "$root"
if [ "${1:-}" = --check ]; then
  bad=0
  for f in "${files[@]}"; do
    if ! "$tool" --dry-run --Werror "$f" >/dev/null 2>&1; then
      echo "format: $f is not formatted (scripts/format.sh formats it)" >&2
      bad=1
    fi
  done
  [ $bad -eq 0 ] && echo "format: ${#files[@]} files formatted"
  exit $bad
fi
"$tool" -i "${files[@]}"
