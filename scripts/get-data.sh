#!/usr/bin/env bash
# Fills DEST (default: datasets/ in the repository, git-ignored) with the default
# dataset and detector model:
#   DEST/bonn_crowd_sub300/      300 RGB-D frames of Bonn RGB-D Dynamic "rgbd_bonn_crowd"
#   DEST/models/yolox_nano.onnx  YOLOX-Nano (COCO), the default person detector
# From ../shared when it is there (linked, not copied); otherwise downloaded from
# the public sources and checked against the checksums in datasets/*.sha256.
# With --whole-sequence, also the whole "rgbd_bonn_crowd" (928 colour, 927 depth
# frames, 31 s; the benchmark of doc/odometry.md):
#   DEST/rgbd_bonn_crowd/        a link to FOLDER when one is given (a TUM-layout
#                                folder with rgb.txt, depth.txt, groundtruth.txt),
#                                otherwise downloaded from the Bonn site.
# Usage: scripts/get-data.sh [--whole-sequence[=FOLDER]] [DEST]
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
whole= whole_from=
case "${1:-}" in
  --whole-sequence) whole=1; shift ;;
  --whole-sequence=*) whole=1 whole_from=${1#--whole-sequence=}; shift ;;
esac
dest=${1:-$root/datasets}
shared=${AVM_SHARED_DIR:-$root/../shared}
bonn_url=${AVM_BONN_URL:-https://www.ipb.uni-bonn.de/html/projects/rgbd_dynamic2019/rgbd_bonn_crowd.zip}
yolox_url=${AVM_YOLOX_URL:-https://github.com/Megvii-BaseDetection/YOLOX/releases/download/0.1.1rc0/yolox_nano.onnx}
# The window of the sequence: the files named in the manifest, ground truth 0.5 s around them.
gt_margin=0.5

die() { echo "get-data: $*" >&2; exit 1; }
mkdir -p "$dest/models"

fetch() {  # fetch URL FILE
  if command -v curl >/dev/null; then curl -fL --retry 2 -o "$2" "$1"
  elif command -v wget >/dev/null; then wget -q -O "$2" "$1"
  else return 1; fi
}

verify() {  # verify MANIFEST DIR
  (cd "$2" && sha256sum --quiet -c "$1") || die "checksum mismatch in $2 (against $1)"
}

# download_sequence DIR: the whole rgbd_bonn_crowd from the Bonn site, unpacked into DIR.
download_sequence() {
  command -v unzip >/dev/null || die "unzip is needed to unpack $bonn_url (apt-get install unzip)"
  mkdir -p "$1"
  echo "get-data: downloading $bonn_url"
  fetch "$bonn_url" "$1/seq.zip" || die "the download of $bonn_url failed (no network? give the unpacked folder: --whole-sequence=FOLDER)"
  unzip -q "$1/seq.zip" -d "$1/unpacked"
  rm "$1/seq.zip"
  local found; found=$(dirname "$(find "$1/unpacked" -name rgb.txt | head -n1)")
  [ -f "$found/rgb.txt" ] || die "$bonn_url: no rgb.txt inside"
  mv "$found"/* "$1/" && rm -rf "$1/unpacked"
}

# The whole sequence: linked from the folder given, or downloaded.
get_whole_sequence() {
  local out=$dest/rgbd_bonn_crowd
  if [ -n "$whole_from" ]; then
    for f in rgb.txt depth.txt groundtruth.txt; do [ -f "$whole_from/$f" ] || die "$whole_from: no $f (not a TUM-layout folder)"; done
    ln -sfn "$(cd "$whole_from" && pwd)" "$out"
    echo "get-data: whole sequence linked from $whole_from"
    return 0
  fi
  [ -f "$out/rgb.txt" ] && return 0
  local tmp; tmp=$(mktemp -d "$dest/.bonn-whole.XXXX")
  trap 'rm -rf "$tmp"' EXIT
  download_sequence "$tmp"
  mv "$tmp" "$out"
  trap - EXIT
  echo "get-data: whole sequence downloaded into $out"
}

get_dataset() {
  local out=$dest/bonn_crowd_sub300
  [ -e "$out/associations.txt" ] || [ -e "$out/rgb.txt" ] && return 0
  if [ -d "$shared/datasets/bonn_crowd_sub300" ]; then
    ln -sfn "$(cd "$shared/datasets/bonn_crowd_sub300" && pwd)" "$out"
    echo "get-data: dataset linked from $shared/datasets/bonn_crowd_sub300"
    return 0
  fi
  local tmp; tmp=$(mktemp -d "$dest/.bonn.XXXX")
  trap 'rm -rf "$tmp"' RETURN
  local src=$dest/rgbd_bonn_crowd
  [ -f "$src/rgb.txt" ] || { download_sequence "$tmp/src"; src=$tmp/src; }
  local part=$tmp/bonn_crowd_sub300
  mkdir -p "$part/rgb" "$part/depth"
  while read -r _ file; do cp "$src/$file" "$part/$file"; done < "$root/datasets/bonn_crowd_sub300.sha256"
  verify "$root/datasets/bonn_crowd_sub300.sha256" "$part"
  for kind in rgb depth; do
    { echo "# $kind (subset of rgbd_bonn_crowd, see datasets/bonn_crowd_sub300.sha256)"; echo "# timestamp filename"
      grep " $kind/" "$root/datasets/bonn_crowd_sub300.sha256" | awk '{print $2}' | sort |
        sed -E "s#^$kind/(.*)\.png\$#\1 $kind/\1.png#"; } > "$part/$kind.txt"
  done
  local t0 t1
  t0=$(grep -v '^#' "$part/depth.txt" | head -n1 | cut -d' ' -f1)
  t1=$(grep -v '^#' "$part/depth.txt" | tail -n1 | cut -d' ' -f1)
  { echo "# ground truth trajectory (subset of rgbd_bonn_crowd/groundtruth.txt)"; echo "# timestamp tx ty tz qx qy qz qw"
    awk -v a="$t0" -v b="$t1" -v m="$gt_margin" '!/^#/ && $1 >= a - m && $1 <= b + m' "$src/groundtruth.txt"; } > "$part/groundtruth.txt"
  mv "$part" "$out"
  echo "get-data: dataset downloaded and verified into $out"
}

get_model() {
  local out=$dest/models/yolox_nano.onnx
  [ -e "$out" ] && return 0
  if [ -f "$shared/models/yolox_nano.onnx" ]; then
    ln -sfn "$(cd "$shared/models" && pwd)/yolox_nano.onnx" "$out"
    echo "get-data: model linked from $shared/models"
    return 0
  fi
  echo "get-data: downloading $yolox_url"
  fetch "$yolox_url" "$out.part" || { rm -f "$out.part"; die "no ../shared and the download of $yolox_url failed"; }
  (cd "$dest/models" && sed 's/yolox_nano.onnx/yolox_nano.onnx.part/' "$root/datasets/yolox_nano.sha256" | sha256sum --quiet -c -) ||
    { rm -f "$out.part"; die "checksum mismatch for $yolox_url"; }
  mv "$out.part" "$out"
  echo "get-data: model downloaded and verified into $out"
}

[ -z "$whole" ] || get_whole_sequence
get_dataset
get_model
