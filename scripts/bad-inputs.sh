#!/usr/bin/env bash
# Runs the programs on bad inputs and writes what each says (exit status and
# output, exactly as printed) as doc/bad-inputs.md, the whole file, so that the
# list there is never typed by hand (doc/reliability.md links to it).
#   scripts/bad-inputs.sh [BUILD_DIR]      (default: build)
# Needs the built programs and ../shared (or $AVM_SHARED_DIR) for a dataset.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=$(cd "${1:-$root/build}" && pwd)/bin
shared=${AVM_SHARED_DIR:-$root/../shared}
doc=$root/doc/bad-inputs.md
for p in avm-map avm-tum2rawlog avm-odometry avm-detect avm-eval; do
  [ -x "$bin/$p" ] || { echo "bad-inputs.sh: $bin/$p not built" >&2; exit 1; }
done

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"   # relative names, so that the messages show no temporary folder

# A 3-frame copy of the Bonn sequence whose ground truth starts 6 ms after
# the first frame (its first pose after the frame moved there).
mkdir -p late/rgb late/depth
head -3 "$shared/datasets/bonn_crowd_sub300/associations.txt" > late/associations.txt
while read -r _ rgb _ depth; do
  cp "$shared/datasets/bonn_crowd_sub300/$rgb" "late/$rgb"
  cp "$shared/datasets/bonn_crowd_sub300/$depth" "late/$depth"
done < late/associations.txt
first=$(awk 'NR==1{print $3}' late/associations.txt)
awk -v t0="$first" '/^#/ {print; next} $1 > t0 {if (!moved) {$1 = sprintf("%.5f", t0 + 0.006); moved = 1} print}' \
  "$shared/datasets/bonn_crowd_sub300/groundtruth.txt" > late/groundtruth.txt

map_ini() {  # map_ini FILE CREATION_LINE [INSERTION_LINE]: avm-map gets as far as creating the map
  printf '[pipeline]\ndetect_every_n = 0\n[map]\nadaptiveOctoMap_count = 1\n[map_adaptiveOctoMap_00_creationOpts]\n%s\n[map_adaptiveOctoMap_00_insertOpts]\n%s\n' \
    "$2" "${3:-}" > "$1"
}
map_ini map.ini ""
map_ini resolution.ini "low_resolution = -1"
map_ini resolution-abc.ini "low_resolution = abc"
map_ini probhit.ini "low_probHit = 1.5"
map_ini divide.ini "high_resolution = 0.07"
map_ini policy.ini "" "switch_policy = sometimes"
printf '[odometry]\nnum_features = abc\n' > odometry-abc.ini
printf '[odometry]\nnum_features =\n' > odometry-empty.ini
printf '[odometry]\nnum_features = 1e12\n' > odometry-huge.ini
printf '[odometry]\nnum_features = 10\n' > odometry-few.ini
printf '[odometry]\nmask_people = maybe\n' > odometry-bool.ini
printf '[detection]\nscore_threshold = 1.5\n' > detection-range.ini
printf '[detection]\ninput_width = 3.5\n' > detection-fraction.ini

rows=""
try() {  # try "WHAT IS WRONG" PROGRAM ARGS...: one table row
  local what=$1; shift
  local status=0 out
  out=$("$bin/$@" 2>&1) || status=$?
  # MRPT's logger's INFO lines (avm-map names its detector) are not the error.
  out=$(printf '%s\n' "$out" | grep -v '|INFO |' || true)
  out=${out//|/\\|}
  rows+="| $what | \`$*\` | $status | \`${out//$'\n'/\` <br> \`}\` |"$'\n'
}
try "missing arguments" avm-map
try "unknown option" avm-eval --typo est.txt gt.txt
try "argument not a number" avm-tum2rawlog --compression abc late out.rawlog
try "ini file missing" avm-map -c nope.ini -r none.rawlog
try "rawlog missing" avm-map -c map.ini -r none.rawlog
try "non-number" avm-odometry -c odometry-abc.ini in.rawlog out.txt
try "empty value" avm-odometry -c odometry-empty.ini in.rawlog out.txt
try "integer out of range" avm-odometry -c odometry-huge.ini in.rawlog out.txt
try "below the minimum" avm-odometry -c odometry-few.ini in.rawlog out.txt
try "not a bool" avm-odometry -c odometry-bool.ini in.rawlog out.txt
try "probability above 1" avm-detect -c detection-range.ini --image x.png
try "fraction for an integer" avm-detect -c detection-fraction.ini --image x.png
try "map: negative resolution" avm-map -c resolution.ini -r none.rawlog
try "map: non-number" avm-map -c resolution-abc.ini -r none.rawlog
try "map: probability above 1" avm-map -c probhit.ini -r none.rawlog
try "map: resolutions that do not divide" avm-map -c divide.ini -r none.rawlog
try "map: unknown switch_policy" avm-map -c policy.ini -r none.rawlog
try "non-number given with --set" avm-map -c map.ini -r none.rawlog --set odometry:num_features=abc
try "non-number in [pipeline]" avm-map -c map.ini -r none.rawlog --set pipeline:detect_every_n=abc
mkdir -p never-ran damaged
printf 'avm-checkpoint' > damaged/checkpoint.bin
try "resume: no checkpoint in the folder" avm-map --resume never-ran
try "resume: a damaged checkpoint" avm-map --resume damaged
try "resume with another configuration" avm-map --resume damaged -c map.ini
try "ground truth starts 6 ms after the first frame" avm-tum2rawlog late late.rawlog
try "the same with --trim-to-ground-truth" avm-tum2rawlog -q --trim-to-ground-truth late late.rawlog

{
  echo "# Bad input: what each program says"
  echo
  echo "Made by \`scripts/bad-inputs.sh\`: each program on a bad input, its exit status and all it printed (MRPT's INFO"
  echo "log lines left out). Tests: \`ProgramErrors.*\`, \`AllPrograms/Program.*\`, \`IniValues.*\`, \`ErrorMessages.*\`,"
  echo "\`TumToRawlogBadInput.*\`."
  echo
  echo "| input | command | exit | output |"
  echo "|---|---|---|---|"
  printf '%s' "$rows"
} > "$work/bad-inputs.md"
cp "$work/bad-inputs.md" "$doc"
echo "bad-inputs.sh: $doc written"
