#!/usr/bin/env bash
# The size limits of the code: no .h or .cpp of app/, modules/ or tests/ over
# 600 lines, no function (a brace block directly in a namespace or a class:
# function bodies, lambdas at namespace scope, TEST bodies) over 100 lines,
# counted from the line its signature starts on to its closing brace.
#   scripts/check-sizes.sh          lists what is over, exits 1 if anything is
#   scripts/check-sizes.sh --top N  also prints the N longest functions and files
# Comments, string and character literals (raw strings too) are skipped, so
# their braces do not count.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
top=0
[ "${1:-}" = --top ] && top=${2:?--top N}
cd "$root"
mapfile -d '' files < <(find app modules tests \( -name '*.h' -o -name '*.cpp' \) -print0 | sort -z)
report=$(awk -v maxFn=100 -v maxFile=600 '
function closeHead(c) { head = ""; headLine = 0 }
function isContainer(h) {
	# namespace, class, struct, union, extern "C" (its string is stripped)
	return h ~ /^(template[ \t]*<.*>[ \t]*)?(inline[ \t]+)?(namespace|class|struct|union|extern)([^A-Za-z0-9_]|$)/
}
FNR == 1 {
	if (NR > 1) endFile()
	depth = 0; inComment = 0; raw = ""; head = ""; headLine = 0
	delete container; fnDepth = -1
}
{
	line = $0; out = ""; i = 1; n = length(line)
	while (i <= n) {
		if (raw != "") {                      # inside R"d( ... )d"
			p = index(substr(line, i), ")" raw "\"")
			if (p == 0) { i = n + 1; continue }
			i += p + length(raw) + 1; raw = ""; out = out "\"\""; continue
		}
		if (inComment) {
			p = index(substr(line, i), "*/")
			if (p == 0) { i = n + 1; continue }
			i += p + 1; inComment = 0; continue
		}
		c = substr(line, i, 1); c2 = substr(line, i, 2)
		if (c2 == "//") break
		if (c2 == "/*") { inComment = 1; i += 2; continue }
		if (c == "\"" && substr(line, i - 1, 1) == "R" && match(substr(line, i + 1), /^[^ ()\\]*\(/)) {
			raw = substr(line, i + 1, RLENGTH - 1); i += RLENGTH + 1; continue
		}
		if (c == "\"" || (c == "\x27" && substr(line, i - 1, 1) !~ /[0-9A-Fa-f]/)) {
			q = c; i++
			while (i <= n && substr(line, i, 1) != q) i += (substr(line, i, 1) == "\\") ? 2 : 1
			i++; out = out q q; continue
		}
		out = out c; i++
	}
	if (out ~ /^[ \t]*#/) next                # preprocessor lines
	for (j = 1; j <= length(out); j++) {
		c = substr(out, j, 1)
		if (c == "{") {
			h = head; gsub(/^[ \t]+|[ \t]+$/, "", h)
			if (fnDepth < 0 && (depth == 0 || container[depth])) {
				if (isContainer(h)) container[depth + 1] = 1
				else {
					container[depth + 1] = 0
					if (h !~ /=$/ && h != "") { fnDepth = depth + 1; fnStart = headLine ? headLine : FNR; fnName = h }
				}
			} else container[depth + 1] = 0
			depth++; closeHead()
		} else if (c == "}") {
			if (depth == fnDepth) {
				len = FNR - fnStart + 1
				gsub(/[ \t]+/, " ", fnName)
				if (length(fnName) > 60) fnName = substr(fnName, 1, 57) "..."
				printf "FN %d %s:%d %s\n", len, FILENAME, fnStart, fnName
				fnDepth = -1
			}
			depth--; closeHead()
		} else if (c == ";") closeHead()
		else {
			if (c !~ /[ \t]/ && headLine == 0) headLine = FNR
			head = head c
		}
	}
	head = head " "
}
function endFile() { printf "FILE %d %s\n", lastFnr, lastFile }
{ lastFnr = FNR; lastFile = FILENAME }
END { endFile() }
' "${files[@]}")
bad=0
while read -r kind n where name; do
  if [ "$kind" = FN ] && [ "$n" -gt 100 ]; then echo "sizes: $where: $n lines (over 100): $name" >&2; bad=1; fi
  if [ "$kind" = FILE ] && [ "$n" -gt 600 ]; then echo "sizes: $where: $n lines (over 600)" >&2; bad=1; fi
done <<<"$report"
if [ "$top" -gt 0 ]; then
  echo "longest functions:"; grep '^FN' <<<"$report" | sort -k2,2nr | awk -v n="$top" 'NR <= n' | cut -d' ' -f2-
  echo "longest files:"; grep '^FILE' <<<"$report" | sort -k2,2nr | awk -v n="$top" 'NR <= n' | cut -d' ' -f2-
fi
[ $bad -eq 0 ] && echo "sizes: ${#files[@]} files, none over 600 lines, no function over 100 lines"
exit $bad
