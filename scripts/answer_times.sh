#!/usr/bin/env bash
# Every file named on standard input through `bvhview info` (an .amc with the CMU skeleton of
# tests/data), on one core and under a 4 GB address-space limit, to show that no file takes the
# machine: how long each took, its peak memory and how it ended. Prints "milliseconds peak-KB
# exit-code line", slowest first; exit codes other than 0 and 2 (a panic's 101, an abort's 134,
# a timeout's 124) are listed again at the end, and the slowest answer and the largest peak last.
# Characters are lines of two or three words:
#   character FILE          `positions FILE --character FILE --vertices` (read, bound, skinned)
#   dress TAKE CHARACTER    `convert TAKE --character CHARACTER -o x.glb` (retargeted, written)
#   find DIR -type f -size -1024k | scripts/answer_times.sh [BVHVIEW]   (default target/release)
# With --crafted, the crafted worst cases of the newer inputs instead (`solve` inputs: an .npy
# header claiming 4 GB, sparse files of 1.86 GB, a large CSV; JSON maps of 95,000 keys; MP4 rates;
# characters, made by scripts/hostile_characters), each under the same limits: "milliseconds
# peak-KB exit-code case", slowest first, then the slowest answer and the largest peak.
#   scripts/answer_times.sh --crafted [BVHVIEW]
set -uo pipefail
cd "$(dirname "$0")/.."

if [ "${1:-}" = "--crafted" ]; then
    cli=$(realpath "${2:-target/release/bvhview}")
    walk=$(realpath tests/data/bvh/bvhparser_walk_01.bvh)
    work=$(mktemp -d)
    trap 'rm -rf "$work"' EXIT
    cd "$work" || exit 1
    # A version-2 .npy whose header length is 0xFFFFFFF0 (npyz asked for 4 GB), 27 bytes.
    printf '\x93NUMPY\x02\x00\xf0\xff\xff\xff{{{{{{{{{{{{{{{' >claim.npy
    # Files of 1.86 GB taking no disk, not what their names say.
    truncate -s 1860000000 sparse.npy sparse.csv
    # The positions CSV of 50,000 frames of SMPL's 22 joints (1.1 million rows).
    awk 'BEGIN {
        split("pelvis left_hip right_hip spine1 left_knee right_knee spine2 left_ankle right_ankle spine3 left_foot right_foot neck left_collar right_collar head left_shoulder right_shoulder left_elbow right_elbow left_wrist right_wrist", j, " ")
        print "frame,joint,x,y,z"
        for (f = 0; f < 50000; f++) for (i = 1; i <= 22; i++) printf "%d,%s,%.4f,%.4f,%.4f\n", f, j[i], i * 0.01, 1 + i * 0.02, f * 0.001
    }' >large.csv
    # JSON maps of 95,000 keys: the last repeating the first; the same under a fingerprint.
    awk 'BEGIN { printf "{"; for (i = 0; i < 95000; i++) printf "\"k%06d\": \"x\",\n", i; print "\"k000000\": \"y\"}" }' >many.json
    awk 'BEGIN { printf "{\"skeleton\": {\"abc\": {"; for (i = 0; i < 95000; i++) printf "%s\"k%06d\": \"x\"\n", (i ? "," : ""), i; print "}}}" }' >skeleton.json
    mkdir takes && cp "$walk" takes/
    # Characters: 17,000 skin joints under an 8,000-frame take, 100,000 influences on a vertex,
    # 40,000 bare nodes × 4,000 frames, weights that overflow, a bind scale of 3e38, a stride
    # shorter than its element, a 60,000-corner polygon, cluster indices past the vertices.
    characters=$(realpath "$OLDPWD/scripts/hostile_characters")
    for made in f1 f2 "f4 40000 4000" f5 f6 f7; do
        # shellcheck disable=SC2086
        python3 "$characters/gltf.py" . $made >/dev/null
    done
    python3 "$characters/fbx.py" . tri 60000 >/dev/null
    python3 "$characters/fbx.py" . cl >/dev/null
    cases=(
        "character-17000-joints-8000-frames|convert f1_take.bvh --character f1_17000_joints.glb -o x.glb"
        "character-100000-influences|convert $walk --character f2_many_influences.glb --any-body -o x.glb"
        "character-40000-nodes-4000-frames|positions f4_nodes_frames.glb --character f4_nodes_frames.glb --vertices -o v.npy"
        "character-weights-overflow|positions f5_overflow.glb --character f5_overflow.glb --vertices -o v.npy"
        "character-200000-weights|positions f5_drift.glb --character f5_drift.glb --vertices -o v.npy"
        "character-bind-scale-3e38|snapshot f6_infinite.glb --character f6_infinite.glb -o x.png"
        "character-short-stride|positions f7_stride.glb --character f7_stride.glb --vertices -o v.npy"
        "character-60000-corner-polygon|positions f3_polygon_60000.fbx --character f3_polygon_60000.fbx --vertices -o v.npy"
        "character-cluster-past-vertices|positions f7_clusters.fbx --character f7_clusters.fbx --vertices -o v.npy"
        "npy-header-claims-4GB|solve claim.npy --onto smpl22 --fps 20 -o out.bvh"
        "npy-sparse-1.86GB|solve sparse.npy --onto smpl22 --fps 20 -o out.bvh"
        "humanml3d-sparse-1.86GB|solve sparse.npy --from humanml3d --onto smpl22 --fps 20 -o out.bvh"
        "csv-sparse-1.86GB|solve sparse.csv --onto smpl22 --fps 20 -o out.bvh"
        "csv-50000-frames|solve large.csv --onto smpl22 --fps 20 -o out.bvh"
        "map-95000-keys|retarget $walk --onto smpl22 --map many.json --show-map"
        "map-95000-skeleton-keys|retarget $walk --onto smpl22 --map skeleton.json --show-map"
        "dataset-map-95000-keys|dataset takes --onto smpl22 --map many.json -o out.ds"
        "mp4-fps-0.0137|snapshot $walk --frames 0..3 --fps 0.0137 -o slow.mp4"
        "mp4-fps-1000|snapshot $walk --frames 0..30 --fps 1000 --size 64x64 -o fast.mp4"
        "mp4-fps-one-third|snapshot $walk --frames 0..30 --fps 0.3333333 -o third.mp4"
    )
    results=$(for case in "${cases[@]}"; do
        name=${case%%|*}
        read -r -a args <<<"${case#*|}"
        /usr/bin/time -o time.txt -f "%e %M" prlimit --as=4000000000 taskset -c 0 timeout 60 \
            "$cli" "${args[@]}" >/dev/null 2>&1
        code=$?
        read -r seconds peak < <(tail -n 1 time.txt)
        echo "$(awk -v s="$seconds" 'BEGIN { printf "%d", s * 1000 }') $peak $code $name"
    done | sort -rn)
    echo "$results"
    echo "$results" | awk 'NR == 1 { print "slowest: " $4 " in " $1 " ms" }'
    echo "$results" | sort -k2 -rn | awk 'NR == 1 { print "peak memory: " $4 ", " int($2 / 1024) " MB" }'
    echo "$results" | awk '$3 != 0 && $3 != 2 { print "ended badly: " $0 }'
    exit 0
fi

cli=${1:-target/release/bvhview}
asf=tests/data/asf_amc/heiden_12.asf
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
results=$(while read -r first second third; do
    case "$first" in
        character) args=(positions "$second" --character "$second" --vertices -o "$scratch/v.npy") ;;
        dress) args=(convert "$second" --character "$third" -o "$scratch/x.glb") ;;
        *.amc) args=(info "$asf" --motion "$first") ;;
        *) args=(info "$first") ;;
    esac
    start=$(date +%s%N)
    /usr/bin/time -f %M -o "$scratch/peak" prlimit --as=4000000000 taskset -c 0 timeout 30 \
        "$cli" "${args[@]}" >/dev/null 2>&1
    code=$?
    peak=$(tail -1 "$scratch/peak" 2>/dev/null)
    echo "$(( ($(date +%s%N) - start) / 1000000 )) ${peak:-?} $code $first${second:+ $second}${third:+ $third}"
done | sort -rn)
echo "$results"
echo "$results" | awk '$3 != 0 && $3 != 2 { print "ended badly: " $0 }'
echo "$results" | head -1 | awk '{ print "slowest answer: " $1 " ms (" $0 ")" }'
echo "$results" | sort -k2 -rn | head -1 | awk '{ print "largest peak: " $2 " KB (" $0 ")" }'
