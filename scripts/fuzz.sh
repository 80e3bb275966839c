#!/usr/bin/env bash
# Fuzz one loader or writer with AFL++ through cargo-afl (stable Rust).
#   scripts/fuzz.sh TARGET [EXECUTIONS|SECONDSs] [WORKDIR]   (default 10000000, /tmp/bvhview-fuzz)
# A limit ending in `s` (`600s`) is a time limit in seconds instead of a count of executions.
# TARGET: the loaders bvh, asf, amc, fbx, gltf (whole small FBX/glTF/GLB files of tests/data as
# seeds); the character readers fbx_character, gltf_character (skinned meshes); the writers write_bvh, write_gltf, write_fbx, write_positions; the dataset reader and merge,
# dataset (its seeds: a small dataset's files behind the byte that picks which file they replace);
# retarget map files, map (its seeds: a TOML and a JSON map between the two takes it retargets);
# solve's positions readers and solve onto smpl22, solve (its seeds: the positions CSV and the
# .npy arrays bvhview writes of a CMU walk put on smpl22: frames x 22 x 3, frames x 27 x 3,
# HumanML3D's frames x 263; the first byte, 0x93 or not, picks the reader).
# Seeds come from the repository's corpus at run time and are written under WORKDIR, never into
# the project. Loaders: tests/data (files up to 4 KB whole, the first 2 KB of larger ones, cut at
# a line end: small inputs run faster). Writers: the small whole BVH files of tests/edge,
# tests/oracle/inputs and tests/data, each behind a few first bytes (the byte picks the edits,
# fuzz/src/lib.rs). Crashes land in WORKDIR/TARGET/out/default/crashes.
# The limits every input under 1 MB (AFL's largest) must be answered within are crash
# conditions: an execution past 2 s is a hang (-t 2000), one past 4 GB of address space dies
# and is a crash (-m 4000, in MB).
set -euo pipefail
cd "$(dirname "$0")/.."
target=${1:?usage: scripts/fuzz.sh bvh|asf|amc|fbx|gltf|fbx_character|gltf_character|write_bvh|write_gltf|write_fbx|write_positions|dataset|map|solve [EXECUTIONS] [WORKDIR]}
executions=${2:-10000000}
case "$executions" in
    *s) limit=(-V "${executions%s}") ;;
    *) limit=(-E "$executions") ;;
esac
work=${3:-/tmp/bvhview-fuzz}/$target
data=tests/data

command -v cargo-afl >/dev/null || cargo install cargo-afl
(cd fuzz && cargo afl build --release --bin "$target")

rm -rf "$work" && mkdir -p "$work/in"
seed() { # FILE: whole if small, else its first 8 KB cut at a line end
    local name; name=$(basename "$1")
    if [ "$(stat -c %s "$1")" -le 4096 ]; then cp "$1" "$work/in/$name"
    else head -c 2048 "$1" | sed '$d' > "$work/in/$name"; fi
}
case "$target" in
    bvh) for f in "$data"/bvh/*.bvh "$data"/bvh_malformed/*.bvh; do seed "$f"; done ;;
    asf) for f in "$data"/asf_amc/*.asf; do seed "$f"; done ;;
    amc) for f in "$data"/asf_amc/*.amc; do seed "$f"; done ;;
    # Binary formats are not cut (a cut FBX or GLB is only a truncation): the small ones whole.
    fbx) for f in "$data"/fbx/ufbx/*.fbx; do
             [ "$(stat -c %s "$f")" -le 40000 ] && cp "$f" "$work/in/"; done ;;
    gltf) for f in "$data"/gltf/*.glb "$data"/gltf/*.gltf; do
             [ "$(stat -c %s "$f")" -le 120000 ] && cp "$f" "$work/in/"; done ;;
    # Characters: the committed characters, and the skinned glTF bvhview writes of a
    # small take with its generated skin (a few KB: the fuzzer gets through it fast).
    fbx_character) cp "$data"/characters/*.fbx "$work/in/"
        for f in "$data"/fbx/ufbx/*.fbx; do
            [ "$(stat -c %s "$f")" -le 40000 ] && cp "$f" "$work/in/"; done ;;
    gltf_character)
        cli=target/release/bvhview
        [ -x "$cli" ] || { cli=target/debug/bvhview; cargo build --bin bvhview; }
        "$cli" convert -q tests/oracle/inputs/tiny_crlf.bvh --skin -o "$work/in/skin.glb"
        cp "$data"/characters/*.glb "$work/in/" ;;
    write_bvh|write_gltf|write_fbx|write_positions)
        for f in tests/edge/*.bvh tests/oracle/inputs/*.bvh "$data"/bvh/*.bvh; do
            [ "$(stat -c %s "$f")" -le 4096 ] || continue
            for choice in 00 01 02 04 08 0b 41 83 c5 f1; do
                { printf "\\x$choice"; cat "$f"; } > "$work/in/$choice-$(basename "$f")"
            done
        done ;;
    dataset)
        # Any build of the CLI makes the seed dataset: the one there, else a debug build.
        cli=target/release/bvhview
        [ -x "$cli" ] || { cli=target/debug/bvhview; cargo build --bin bvhview; }
        mkdir -p "$work/takes"
        cp "$data"/bvh/assimp_01_01.bvh "$work/takes/a.bvh"
        "$cli" dataset "$work/takes" -o "$work/seed.ds" --fps 10
        for pick in 0 1 2 3 4; do
            file=$(echo manifest.json group_0/positions.npy group_0/offsets.npy \
                group_0/rest_offsets.npy group_0/skeleton.bvh | cut -d' ' -f$((pick + 1)))
            { printf "\\x0$pick"; head -c 4096 "$work/seed.ds/$file"; } > "$work/in/$pick"
        done ;;
    map)
        printf '%s\n' '# bvhview retarget map: "source joint" = "target joint"' \
            '"Hips" = "hip"  # hips' '"LeftUpLeg" = "lThigh"' '"LThumb" = ""' > "$work/in/map.toml"
        printf '%s\n' '{"Hips": "hip", "LeftArm": "lShldr", "RThumb": null}' > "$work/in/map.json" ;;
    solve)
        # A CMU walk put on smpl22 (24 frames of it: 0.2 s), and what bvhview writes of it.
        cli=target/release/bvhview
        [ -x "$cli" ] || { cli=target/debug/bvhview; cargo build --bin bvhview; }
        mkdir -p "$work/take"
        "$cli" retarget -q "$data"/bvh/bvhparser_walk_01.bvh --onto smpl22 -o "$work/smpl.bvh"
        "$cli" convert -q "$work/smpl.bvh" --frames 0..24 -o "$work/take/walk.bvh"
        "$cli" positions -q "$work/take/walk.bvh" --frames 0..3 -o "$work/in/walk.csv"
        "$cli" positions -q "$work/take/walk.bvh" --frames 5 -o "$work/in/one.csv"
        "$cli" dataset -q "$work/take" -o "$work/points" --fps 20
        cp "$work/points/group_0/positions.npy" "$work/in/points27.npy"
        "$cli" dataset -q "$work/take" -o "$work/hml" --features humanml3d --onto smpl22
        cp "$work/hml/new_joints/000000.npy" "$work/in/joints22.npy"
        cp "$work/hml/new_joint_vecs/000000.npy" "$work/in/vectors263.npy" ;;
    *) echo "unknown target $target" >&2; exit 2 ;;
esac
find "$work/in" -size 0 -delete

AFL_SKIP_CPUFREQ=1 AFL_I_DONT_CARE_ABOUT_MISSING_CRASHES=1 AFL_NO_UI=1 AFL_NO_AFFINITY=1 \
    cargo afl fuzz -i "$work/in" -o "$work/out" "${limit[@]}" -t 2000 -m 4000 "fuzz/target/release/$target" \
    > "$work/afl.log" 2>&1 || true
stats="$work/out/default/fuzzer_stats"
echo "$target: $(grep -E '^(execs_done|run_time|saved_crashes|saved_hangs|corpus_count)' "$stats" | tr -s ' ' | paste -sd';')"
