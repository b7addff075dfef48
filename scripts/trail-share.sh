#!/usr/bin/env bash
# The trail moving people leave: labels every frame with avm-detect
# (--every 1, whole detector boxes), runs avm-map with ground-truth poses, and
# prints avm-trail's table: occupied volume that an octomap reference built
# without the persons' pixels says is free, for avm and single OctoMaps, with
# both yardsticks (the persons' own pixels, their depth band as the ini's person
# layer takes it; whole boxes).
#   scripts/trail-share.sh RAWLOG INI OUTDIR [avm-trail options, e.g. --causes]
set -euo pipefail
rawlog=$(realpath "$1"); ini=$(realpath "$2"); out=$3
shift 3
root=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"; out=$(realpath "$out")
cd "$out"
"$root/build/bin/avm-detect" -q -c "$ini" --root "$root" -r "$rawlog" -o labelled.rawlog --every 1 > detect.log
# The map's folder is named after the ini: avm-trail's row says which avm it was.
name=$(basename "$ini" .ini)
"$root/build/bin/avm-map" -q -c "$ini" -p gt -r "$rawlog" -o "$out/$name" > avm-map.log
"$root/build/bin/avm-trail" -c "$ini" -m "$name" "$@" labelled.rawlog
