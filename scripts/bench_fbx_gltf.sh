#!/usr/bin/env bash
# How fast FBX and glTF come in: loading a ~10 MB FBX take and a ~10 MB GLB with bvhview against
# Blender's own import of the same file, and `convert DIR --to bvh` over a folder of takes.
#   scripts/bench_fbx_gltf.sh [WORKDIR]     (needs Blender: apt-get install blender python3-numpy)
# The takes: CMU 01_01 (tests/data/bvh/assimp_01_01.bvh, 2752 frames at 120 Hz, 31 joints) with
# its frames repeated (2× for the FBX, 3× for the GLB), exported by Blender
# (tests/blender/export_fbx_gltf.py). bvhview is timed as a whole process (`bvhview info FILE`,
# start-up included), Blender inside Blender (tests/blender/import_time.py, start-up excluded):
# the comparison favours Blender. Medians of 3 rounds.
set -euo pipefail
cd "$(dirname "$0")/.."
work=${1:-/tmp/bvhview-fbx-bench}
mkdir -p "$work"
cargo build --release -q --bin bvhview
bvhview=target/release/bvhview
repeat() { # SOURCE TIMES OUT: the take with its frames repeated
    python3 - "$1" "$2" "$3" <<'PY'
import sys
text = open(sys.argv[1], newline="").read()
head, motion = text.split("MOTION", 1)
lines = motion.strip().splitlines()
rows = [l for l in lines[2:] if l.strip()]
times = int(sys.argv[2])
out = head + "MOTION\nFrames: %d\n%s\n" % (len(rows) * times, lines[1].strip())
open(sys.argv[3], "w").write(out + "\n".join(rows * times) + "\n")
PY
}
repeat tests/data/bvh/assimp_01_01.bvh 2 "$work/cmu_x2.bvh"
repeat tests/data/bvh/assimp_01_01.bvh 3 "$work/cmu_x3.bvh"
BVHVIEW_FRAMES=0 blender -b --factory-startup --python tests/blender/export_fbx_gltf.py -- \
    "$work/x2" "$work/cmu_x2.bvh" >/dev/null 2>&1
BVHVIEW_FRAMES=0 blender -b --factory-startup --python tests/blender/export_fbx_gltf.py -- \
    "$work/x3" "$work/cmu_x3.bvh" >/dev/null 2>&1
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
for file in "$work/x2/fbx/cmu_x2.fbx" "$work/x3/gltf/cmu_x3.glb"; do
    size=$(stat -c %s "$file")
    ours=$(for _ in 1 2 3; do
        /usr/bin/time -f %e "$bvhview" info "$file" 2>&1 >/dev/null | tail -1
    done | median)
    theirs=$(blender -b --factory-startup --python tests/blender/import_time.py -- "$file" 3 2>/dev/null |
        awk '/^median/ {print $2}')
    frames=$("$bvhview" info "$file" | awk '/^frames:/ {print $2}')
    echo "$(basename "$file"): $size bytes, $frames frames: bvhview ${ours}s, Blender ${theirs}s"
done
# A folder of takes converted to BVH on all cores by `convert DIR` (the FBX test files, 8 copies
# of each), the median of 3.
rm -rf "$work/folder" && mkdir -p "$work/folder"
for k in 1 2 3 4 5 6 7 8; do
    for f in tests/data/fbx/*.fbx; do cp "$f" "$work/folder/$k-$(basename "$f")"; done
done
took=$(for _ in 1 2 3; do
    rm -rf "$work/out"
    /usr/bin/time -f %e "$bvhview" convert "$work/folder" -o "$work/out" --to bvh 2>&1 >/dev/null | tail -1
done | median)
echo "convert DIR: $(ls "$work"/folder/*.fbx | wc -l) FBX takes to BVH on $(nproc) cores: ${took}s"
