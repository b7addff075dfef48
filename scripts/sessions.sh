#!/usr/bin/env bash
# Mapping a building over several runs, measured: sessions cut from the whole
# rgbd_bonn_crowd (avm-tum2rawlog --frames), the first with ground truth in
# its rawlog, every continuation without (a real next run has none), each
# continuing the one before with avm-map --continue. For each chain: how many
# of each continuation's frames were placed in the earlier sessions' map, the
# ATE of all the sessions' poses together under one alignment, the loops
# closed, the CPU a frame of the last session beside a fresh run of the same
# frames (without, and apart, the map rebuild that a closed loop makes at the
# end), and the session's size and load time; on twelve more chains, the
# placement and the ATE alone; and the same space mapped
# over sessions at ground-truth poses against one run of the same frames in
# the same order (IoU of the occupied space, avm-eval --maps). Writes
# doc/sessions-results.md whole, with the commands.
#
# Usage: scripts/sessions.sh [--out FILE] [INI]
#          the doc's chains, into doc/sessions-results.md (or FILE)
#        scripts/sessions.sh --chain FIRST:LAST FIRST:LAST [...] [--gt | --no-cpu] [INI]
#          one chain of cuts of the whole (trimmed) sequence, printed
#          (--gt: at ground-truth poses, every cut with its ground truth,
#          compared with one run of the same frames in the same order;
#          --no-cpu: placement and ATE only, without the CPU runs)
# Needs the whole sequence in datasets/ (scripts/get-data.sh --whole-sequence).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${AVM_BUILD_DIR:-$root/build}
doc=$root/doc/sessions-results.md
ini=ini/default.ini
chain=() groundTruth=0 cpu=1 last="" placed=() loops=0 cpuCells=""
while [ $# -gt 0 ]; do
  case $1 in
    --out) doc=$2; shift 2 ;;
    --chain) shift; while [ $# -gt 0 ] && [[ $1 == *:* ]]; do chain+=("$1"); shift; done ;;
    --gt) groundTruth=1; shift ;;
    --no-cpu) cpu=0; shift ;;
    -*) echo "sessions: unknown option $1 (see the header of $0)" >&2; exit 2 ;;
    *) ini=$1; shift ;;
  esac
done
out=output/sessions  # relative to the root, as the printed commands are
work=$root/$out

source "$root/scripts/prepare.sh"
avm_prepare "$build" -DCMAKE_BUILD_TYPE=Release avm-map avm-eval >&2
whole=$(avm_required_whole_sequence "$build" sessions)
gt=${whole%.rawlog}_groundtruth.txt
cd "$root"
mkdir -p "$work"

# cut FIRST:LAST [gt]: a rawlog of those frames of the trimmed whole sequence,
# made once; without ground truth unless asked.
cut() {
  local name=frames-${1/:/-}${2:+-gt} without=--no-gt
  [ -z "${2:-}" ] || without=
  if [ ! -f "$work/$name.rawlog" ]; then
    # shellcheck disable=SC2086  # --no-gt or nothing
    "$build/bin/avm-tum2rawlog" -q --camera bonn --gt-body bonn --embed-images --compression 0 \
      --trim-to-ground-truth --frames "$1" $without datasets/rgbd_bonn_crowd "$work/$name.rawlog" >&2
  fi
  echo "$out/$name.rawlog"
}

ate() { "$build/bin/avm-eval" "$1" "$gt" | awk '/^ATE/ {print $3}'; }
commands=()
run() { commands+=("build/bin/avm-map -q $*"); "$build/bin/avm-map" -q "$@" >/dev/null; }

# perFrame DIR: the CPU a frame [ms] of the run in DIR without its map rebuild
# (a pass over all the run's frames again, made once after a loop closed);
# and the rebuild's, as "frames rebuild".
perFrame() {
  local frames rebuild
  frames=$(avm_stat "$1" frames)
  rebuild=$(avm_stat "$1" cpu_seconds)  # map_rebuild's, the only one of that name
  awk -v c="$(avm_stat "$1" cpu_ms_per_frame)" -v f="$frames" -v r="${rebuild:-0}" \
    'BEGIN { printf "%f %f", c - 1e3 * r / f, 1e3 * r / f }'
}

# cpuPair PREV RAWLOG [BEFORE ONERUN]: the CPU a frame of RAWLOG continuing
# PREV and of RAWLOG run fresh, "continued / fresh" [ms]; with BEFORE and
# ONERUN (rawlogs of the frames before RAWLOG's, and of those and RAWLOG's:
# all the sessions' frames as one run), also the CPU a frame of RAWLOG's
# frames within that one run: ONERUN's CPU less BEFORE's, over RAWLOG's
# frames; a run of ONERUN has the earlier frames' map in view at those frames,
# as the continuation has. Each the median of five runs on one core,
# alternating, so that the machine's load falls on all alike; the map rebuild
# apart, then its share of the first two, "continued / fresh" [ms a frame].
# Into $cpuCells, not printed: the commands it runs are listed in the doc,
# which a command substitution's subshell would lose.
cpuPair() {
  local i cont=() fresh=() oneRun=() contRebuild=() freshRebuild=() c f b o
  commands+=("taskset -c 0 build/bin/avm-map -q --continue $1 -r $2 -o $out/cpu-continued  # 5 times, alternating with:"
    "taskset -c 0 build/bin/avm-map -q -c $ini -r $2 -o $out/cpu-fresh  # the medians")
  [ -z "${3:-}" ] || commands+=("taskset -c 0 build/bin/avm-map -q -c $ini -r $3 -o $out/cpu-before  # and"
    "taskset -c 0 build/bin/avm-map -q -c $ini -r $4 -o $out/cpu-one-run")
  # pinned NAME ARGS...: avm-map ARGS on the first core into cpu-NAME; its perFrame.
  pinned() {
    local name=$1
    shift
    rm -rf "${work:?}/cpu-$name"
    taskset -c 0 "$build/bin/avm-map" -q "$@" -o "$out/cpu-$name" >/dev/null
    perFrame "$work/cpu-$name"
  }
  for i in 1 2 3 4 5; do
    read -r c f <<<"$(pinned continued --continue "$1" -r "$2")"
    cont+=("$c") contRebuild+=("$f")
    read -r c f <<<"$(pinned fresh -c "$ini" -r "$2")"
    fresh+=("$c") freshRebuild+=("$f")
    [ -n "${3:-}" ] || continue
    read -r b _ <<<"$(pinned before -c "$ini" -r "$3")"
    read -r o _ <<<"$(pinned one-run -c "$ini" -r "$4")"
    oneRun+=("$(awk -v b="$b" -v nb="$(avm_stat "$work/cpu-before" frames)" -v o="$o" \
      -v no="$(avm_stat "$work/cpu-one-run" frames)" -v f="$(avm_stat "$work/cpu-fresh" frames)" \
      'BEGIN { print (o * no - b * nb) / f }')")
  done
  median() { printf '%s\n' "$@" | sort -g | sed -n 3p; }
  cpuCells=$(printf '%.1f / %.1f | %s | %.1f / %.1f' "$(median "${cont[@]}")" "$(median "${fresh[@]}")" \
    "$([ ${#oneRun[@]} = 0 ] && echo - || printf '%.1f' "$(median "${oneRun[@]}")")" \
    "$(median "${contRebuild[@]}")" "$(median "${freshRebuild[@]}")")
}

# runChain POSES CUT...: each cut continuing the one before; sets $last (the
# last session's folder), $lastPrevious and $lastRawlog (what it continued,
# and its rawlog), $placed (each continuation's placed frames) and $loops
# (closed in all the sessions).
runChain() {
  local poses=$1 name="" prev="" dir rawlog first=1
  shift
  placed=() loops=0
  for c in "$@"; do
    name=${name:+$name+}${c/:/-}
    dir=$work/$poses-$name
    if [ $first = 1 ]; then
      run -c "$ini" -p "$poses" -r "$(cut "$c" gt)" -o "$out/$poses-$name"
    else
      [ "$poses" = gt ] && rawlog=$(cut "$c" gt) || rawlog=$(cut "$c")
      run --continue "$prev" -p "$poses" -r "$rawlog" -o "$out/$poses-$name"
      lastPrevious=$prev lastRawlog=$rawlog
      local frames unplaced
      frames=$(echo "$c" | awk -F: '{print $2 - $1 + 1}')
      unplaced=$(avm_stat "$dir" unplaced_frames)
      placed+=("$(awk -v f="$frames" -v u="$unplaced" 'BEGIN { printf "%d / %d (%.1f %%)", f - u, f, 100 * (f - u) / f }')")
    fi
    loops=$((loops + $(avm_stat "$dir" odometry_loops_closed)))
    first=0
    prev=$out/$poses-$name
  done
  last=$work/$poses-$name
}

# contiguous CUT...: the cuts start at frame 0 and leave no frame out between them.
contiguous() {
  local next=0 c
  for c in "$@"; do
    [ "${c%:*}" = "$next" ] || return 1
    next=$((${c#*:} + 1))
  done
}

# placedCell: each continuation's placed frames, for a table cell.
placedCell() { printf '%s; ' "${placed[@]}" | sed 's/; $//'; }

# chainRow CUT...: the chain at the odometry's poses, its table row.
chainRow() {
  runChain vo "$@"
  local load
  load=$(sed -n 's/.*loaded in \([0-9.]*\) s.*/\1/p' "$last/avm-map.log" | tail -1)
  # The last session's frames run fresh: the CPU a frame a continuation is
  # held to; and within one run of all the chain's frames, where its cuts
  # leave no frames out between them.
  local lastCut=${*: -1} oneRun=()
  local lastFirst=${lastCut%:*} lastLast=${lastCut#*:}
  if contiguous "$@"; then oneRun=("$(cut "0:$((lastFirst - 1))" gt)" "$(cut "0:$lastLast" gt)"); fi
  cpuPair "$lastPrevious" "$lastRawlog" "${oneRun[@]}"
  printf '| %s | %s | %s | %s | %s | %.1f MB, %s s |\n' "$*" "$(placedCell)" \
    "$(ate "$last/trajectory.txt")" "$loops" "$cpuCells" \
    "$(awk -v b="$(stat -c %s "$last/session.bin")" 'BEGIN { printf "%.1f", b / 1e6 }')" "${load:-?}"
}

# accuracyRow CUT...: the chain at the odometry's poses, placement and ATE
# only (no CPU runs): more cuts than the costed ones, at other places of
# the sequence, in and out of order, with and without gaps.
accuracyRow() {
  runChain vo "$@"
  printf '| %s | %s | %s | %s |\n' "$*" "$(placedCell)" \
    "$(ate "$last/trajectory.txt")" "$loops"
}

# spaceRow CUT...: the chain at ground-truth poses against one run of the
# same frames in the same order: the whole sequence for cuts of it in order,
# else the cuts' rawlogs one after the other (a rawlog is a stream of
# observations: concatenated, they are one).
spaceRow() {
  local name reference lastCut=${*: -1} of
  name=$(IFS=+; echo "$*" | sed 's/:/-/g')
  if contiguous "$@" && [ "${lastCut#*:}" = "$(($(avm_stat "$work/gt-whole" frames) - 1))" ]; then
    reference=gt-whole of="the whole sequence"
  else
    reference=gt-one-run-$name of="the cuts in this order"
    local parts=()
    for c in "$@"; do parts+=("$(cut "$c" gt)"); done
    commands+=("cat ${parts[*]} > $out/frames-$name-gt.rawlog")
    cat "${parts[@]}" >"$work/frames-$name-gt.rawlog"
    run -c "$ini" -p gt -r "$out/frames-$name-gt.rawlog" -o "$out/$reference"
  fi
  runChain gt "$@"
  commands+=("build/bin/avm-eval --maps $out/$reference $out/gt-$name")
  "$build/bin/avm-eval" --maps "$work/$reference" "$work/gt-$name" | awk -v n="$*" -v of="$of" '
    /^occupied/ {s = $3 " / " $5 ", IoU " $NF} /^low/ {l = $NF} /^high/ {h = $NF}
    END {printf "| %s | %s | %s | %s | %s |\n", n, of, s, l, h}'
}

tableHead() {
  echo "| sessions (frames of the whole sequence) | placed, each continuation | ATE, all sessions [m] | loops closed | CPU a frame, last session, one core: continued / fresh [ms] | the same frames within one run of all [ms] | its map rebuild after a loop, a frame: continued / fresh [ms] | session.bin, load |"
  echo "|---|---|---|---|---|---|---|---|"
}
accuracyHead() {
  echo "| more sessions (frames of the whole sequence) | placed, each continuation | ATE, all sessions [m] | loops closed |"
  echo "|---|---|---|---|"
}
spaceHead() {
  echo "| sessions at ground-truth poses | one run of | occupied voxels (0.05 m): one run / sessions, IoU | low tree IoU | high tree IoU |"
  echo "|---|---|---|---|---|"
}

if [ ${#chain[@]} -gt 0 ]; then
  if [ "$groundTruth" = 1 ]; then
    run -c "$ini" -p gt -r "$whole" -o "$out/gt-whole"
    spaceHead
    spaceRow "${chain[@]}"
  elif [ "$cpu" = 1 ]; then
    tableHead
    chainRow "${chain[@]}"
  else
    accuracyHead
    accuracyRow "${chain[@]}"
  fi
  exit 0
fi

tmp=$(mktemp)
{
  tableHead
  chainRow 0:462 463:925
  chainRow 0:462 600:925
  chainRow 0:308 309:617 618:925
  chainRow 463:925 0:462
  echo
  accuracyHead
  for c in "0:199 200:925" "0:299 300:925" "0:699 700:925" "0:800 801:925" "100:500 501:925" "0:399 500:925" \
    "0:462 250:700" "0:150 151:450 451:925" "0:462 463:700 701:925" "300:925 0:299" "463:925 100:400" "600:925 0:400"; do
    # shellcheck disable=SC2086  # the cuts, one word each
    accuracyRow $c
  done
  echo
  run -c "$ini" -p gt -r "$whole" -o "$out/gt-whole"
  spaceHead
  spaceRow 0:462 463:925
  spaceRow 463:925 0:462
} >"$tmp"
# Without --continue: the second half run on its own lives in a world of its own.
run -c "$ini" -r "$(cut 463:925)" -o "$out/vo-alone-463-925"
cat "$work/vo-0-462/trajectory.txt" <(grep -v '^#' "$work/vo-alone-463-925/trajectory.txt") >"$work/vo-0-462-and-alone.txt"
alone=$(ate "$work/vo-0-462-and-alone.txt")

{
  echo "# Sessions: measured"
  echo
  echo "Generated by \`scripts/sessions.sh\` ($(date -u +%Y-%m-%d), $(git rev-parse --short HEAD)$(git diff --quiet HEAD -- modules app || echo -dirty),"
  echo "$(lscpu | sed -n 's/^Model name: *//p' | head -1), $(nproc) cores); what the figures mean: [sessions.md](sessions.md)."
  echo "Cuts of the whole \`rgbd_bonn_crowd\` (926 frames after trimming to its ground truth) with"
  echo "\`avm-tum2rawlog --trim-to-ground-truth --frames FIRST:LAST\`, every continuation with \`--no-gt\`; ATE of"
  echo "the chain's last \`trajectory.txt\` (all its sessions' poses) against the whole sequence's ground truth,"
  echo "one SE(3) alignment (\`avm-eval\`). Within one run: the CPU of a run of frames 0 to the last session's"
  echo "last less that of a run of the frames before the last session's, over its frames (- where the cuts leave frames out)."
  echo
  awk 'BEGIN { RS = "" } NR == 1' "$tmp"
  echo
  echo "The same on more cuts, placement and ATE only:"
  echo
  awk 'BEGIN { RS = "" } NR == 2' "$tmp"
  echo
  echo "Without \`--continue\`, the second half run alone lives in a world of its own: with the first half's"
  echo "trajectory under one alignment, ATE $alone m."
  echo
  awk 'BEGIN { RS = "" } NR == 3' "$tmp"
  echo
  echo "Commands (from the repository's root, in this order):"
  echo
  echo '```sh'
  printf '%s\n' "${commands[@]}"
  echo '```'
} >"$doc.tmp"
mv "$doc.tmp" "$doc"
rm -f "$tmp"
echo "sessions: wrote ${doc#"$root/"}" >&2
