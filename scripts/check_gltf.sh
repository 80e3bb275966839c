#!/usr/bin/env bash
# The glTF export checked by the Khronos glTF-Validator (npm package gltf-validator, pinned in
# tests/gltf_validator/package.json, installed into target/tools): every corpus take that loads is
# converted to .glb, with and without --skin, plus one .gltf, and each must have 0 errors.
# Usage: scripts/check_gltf.sh [BVHVIEW]. The last line is "gltf-validator: N files, F failed";
# the exit status is 0 only when every file converted and validated.
set -euo pipefail
cd "$(dirname "$0")/.."
cli=${1:-target/debug/bvhview}
tools=${CARGO_TARGET_DIR:-target}/tools/gltf-validator

if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        echo "installing: nodejs npm (for the glTF validator)"
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends nodejs npm >/dev/null
    else
        echo "gltf-validator: node and npm are missing (apt-get install nodejs npm)" >&2
        echo "gltf-validator: 0 files, 1 failed"
        exit 1
    fi
fi
mkdir -p "$tools"
cp tests/gltf_validator/package.json tests/gltf_validator/validate.js "$tools/"
if [ ! -d "$tools/node_modules/gltf-validator" ]; then
    npm install --prefix "$tools" --no-audit --no-fund --loglevel=error >/dev/null
fi

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
converted=0
failed=0
convert() { # convert NAME MAY_REFUSE INPUT...
    local name=$1 may_refuse=$2
    shift 2
    if ! "$cli" convert -q "$@" -o "$out/$name.glb" 2>"$out/error"; then
        if [ "$may_refuse" = yes ]; then
            return # a malformed file is refused with its error; nothing to validate
        fi
        echo "convert $*: $(cat "$out/error")" >&2
        failed=$((failed + 1))
        return
    fi
    "$cli" convert -q "$@" --skin -o "$out/$name.skin.glb" 2>/dev/null || {
        echo "convert --skin $*: failed" >&2
        failed=$((failed + 1))
    }
    converted=$((converted + 1))
}
folders=(tests/data)
[ -d ../shared/data ] && folders+=(../shared/data)
for folder in "${folders[@]}"; do
    tag=$(basename "$(dirname "$folder")")
    for file in "$folder"/bvh/*.bvh "$folder"/bvh_malformed/*.bvh; do
        [ -e "$file" ] || continue
        may_refuse=no
        [[ $file == */bvh_malformed/* ]] && may_refuse=yes
        convert "$tag.$(basename "$file" .bvh)" "$may_refuse" "$file"
    done
    for asf in "$folder"/asf_amc/*.asf; do
        [ -e "$asf" ] || continue
        for amc in "${asf%.asf}"_*.amc; do
            [ -e "$amc" ] || continue
            convert "$tag.$(basename "$amc" .amc)" no "$asf" --motion "$amc"
        done
    done
done
# Characters: takes put on each committed character, and each on itself.
for character in tests/data/characters/*.fbx tests/data/characters/*.glb; do
    name=$(basename "$character")
    "$cli" convert -q tests/data/bvh/bvh11_131_01.bvh --frames 0..60 --character "$character" \
        -o "$out/walk_on_${name%.*}_${name##*.}.glb" || failed=$((failed + 1))
    "$cli" convert -q "$character" --character "$character" -o "$out/own_${name%.*}_${name##*.}.gltf" \
        || failed=$((failed + 1))
done
"$cli" convert -q tests/oracle/inputs/tiny_crlf.bvh -o "$out/tiny_crlf.gltf"
"$cli" convert -q tests/oracle/inputs/tiny_crlf.bvh --skin -o "$out/tiny_crlf.skin.gltf"

files=("$out"/*.glb "$out"/*.gltf)
node "$tools/validate.js" "${files[@]}" | tee "$out/report" || true
bad=$(grep -c ': [1-9][0-9]* errors' "$out/report" || true)
total=${#files[@]}
echo "gltf-validator: $total files, $((bad + failed)) failed"
[ "$bad" -eq 0 ] && [ "$failed" -eq 0 ]
