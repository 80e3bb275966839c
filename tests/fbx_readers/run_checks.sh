#!/usr/bin/env bash
# FBX out read by two readers nobody here wrote: assimp (Debian's libassimp, through
# check_assimp.cpp) and three.js's FBXLoader (npm `three`, pinned in package.json, through
# check_three.mjs). Every take of tests/data (BVH, the ASF/AMC pair, FBX, glTF; and the whole
# corpus in ../shared/data when it is beside the checkout) is converted to FBX by bvhview, read
# by each reader, and compared by compare.py with what bvhview says of the source take: node
# tree, animation, duration, and every joint at frames 0, 1, N/2 and N-1 within 1e-4 of the
# figure's height.
#
# Usage: tests/fbx_readers/run_checks.sh [BVHVIEW] [WORKDIR]
# What a reader needs is installed when missing: as root, apt-get installs libassimp-dev,
# pkg-config and g++ (assimp) and nodejs and npm (three.js); npm installs three into
# ${CARGO_TARGET_DIR:-target}/tools/fbx-readers. A reader that cannot be set up is skipped with
# one line ("fbx readers: three.js skipped: ..."). The last line is
# "fbx readers: N files checked, F failed" (readers: ...); the exit status is F.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
cli=${1:-$root/target/debug/bvhview}
if [ $# -ge 2 ]; then
    work=$2
    mkdir -p "$work"
else
    work=$(mktemp -d)
    trap 'rm -rf "$work"' EXIT
fi
target=${CARGO_TARGET_DIR:-$root/target}
case $target in /*) ;; *) target=$root/$target ;; esac
tools=$target/tools/fbx-readers
mkdir -p "$tools"

apt_install() { # apt_install PACKAGE...: as root only; quiet
    [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null || return 1
    echo "installing: $* (for the FBX reader checks)"
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$@" >/dev/null
}

readers=()
skipped=()
# assimp: the library and its headers, built against with g++.
if ! { command -v g++ >/dev/null && command -v pkg-config >/dev/null && pkg-config --exists assimp; }; then
    apt_install libassimp-dev pkg-config g++ || true
fi
if command -v g++ >/dev/null && command -v pkg-config >/dev/null && pkg-config --exists assimp; then
    # shellcheck disable=SC2046
    if g++ -O1 -std=c++17 "$here/check_assimp.cpp" -o "$tools/check_assimp" $(pkg-config --cflags --libs assimp) \
        2>"$work/assimp.build"; then
        readers+=(assimp)
    else
        cat "$work/assimp.build" >&2
        skipped+=("assimp: check_assimp.cpp does not build against libassimp $(pkg-config --modversion assimp)")
    fi
else
    skipped+=("assimp: libassimp-dev, pkg-config or g++ missing (apt-get install libassimp-dev pkg-config g++)")
fi
# three.js: node, and three from npm into the tools folder.
if ! { command -v node >/dev/null && command -v npm >/dev/null; }; then
    apt_install nodejs npm || true
fi
if command -v node >/dev/null && command -v npm >/dev/null; then
    cp "$here/package.json" "$here/check_three.mjs" "$tools/"
    want=$(node -p "require('$here/package.json').dependencies.three")
    have=$(node -p "try { require('$tools/node_modules/three/package.json').version } catch { '' }")
    if [ "$have" != "$want" ]; then
        npm install --prefix "$tools" --no-audit --no-fund --loglevel=error >"$work/npm.log" 2>&1 || true
        have=$(node -p "try { require('$tools/node_modules/three/package.json').version } catch { '' }")
    fi
    if [ "$have" = "$want" ]; then
        readers+=(three)
    else
        skipped+=("three.js: npm could not install three@$want ($(tail -n 1 "$work/npm.log" 2>/dev/null))")
    fi
else
    skipped+=("three.js: node and npm missing (apt-get install nodejs npm)")
fi
for line in "${skipped[@]}"; do
    echo "fbx readers: $line: skipped"
done
if [ ${#readers[@]} -eq 0 ]; then
    echo "fbx readers: 0 files checked, 0 failed (no reader could be set up)"
    exit 0
fi

checked=0
failed=0
declare -A done_names
check() { # check NAME [--bone-ends] INPUT... (INPUT: a file, or an ASF and --motion AMC)
    local name=$1 ends=()
    shift
    if [ "$1" = --bone-ends ]; then
        ends=(--bone-ends)
        shift
    fi
    local w=$work/$name
    checked=$((checked + 1))
    if ! "$cli" convert -q "$@" -o "$w.fbx" 2>"$w.err" || ! "$cli" convert -q "$@" -o "$w.bvh" 2>>"$w.err" \
        || ! "$cli" positions -q "$@" -o "$w.csv" 2>>"$w.err" || ! "$cli" info "$@" >"$w.info" 2>>"$w.err"; then
        echo "$name: FAIL: bvhview: $(head -c 300 "$w.err")"
        failed=$((failed + 1))
        return
    fi
    local frames take
    frames=$(awk '/^frames:/ { print $2 }' "$w.info")
    take=$("$cli" info "$w.fbx" 2>/dev/null | sed -n "s/^  0: '\(.*\)', [0-9]* frames\?, .*/\1/p" | head -n 1)
    local at=()
    for f in 0 1 $((frames / 2)) $((frames - 1)); do
        [ "$f" -ge 0 ] && [ "$f" -lt "$frames" ] && [[ " ${at[*]} " != *" $f "* ]] && at+=("$f")
    done
    local dumps=()
    for reader in "${readers[@]}"; do
        case $reader in
            assimp) "$tools/check_assimp" "$w.fbx" "$frames" "${at[@]}" >"$w.assimp.json" 2>"$w.assimp.err" ;;
            three) node "$tools/check_three.mjs" "$w.fbx" "$frames" "${at[@]}" >"$w.three.json" 2>"$w.three.err" ;;
        esac
        dumps+=("$w.$reader.json")
    done
    if ! python3 "$here/compare.py" --hierarchy "$w.bvh" --positions "$w.csv" --info "$w.info" --take "$take" \
        "${ends[@]}" "${dumps[@]}" >"$w.compare" 2>&1; then
        failed=$((failed + 1))
    fi
    sed "s/^/$name: /" "$w.compare"
}

folders=("$root/tests/data")
[ -d "$root/../shared/data" ] && folders+=("$(cd "$root/../shared/data" && pwd)")
for folder in "${folders[@]}"; do
    # A copy of a take already checked (the shared corpus holds tests/data's) is not checked twice.
    for file in "$folder"/bvh/*.bvh "$folder"/fbx/*.fbx "$folder"/gltf/*.glb; do
        [ -e "$file" ] || continue
        name=$(basename "$file")
        [ -n "${done_names[$name]:-}" ] && continue
        done_names[$name]=1
        check "$name" "$file"
    done
    for asf in "$folder"/asf_amc/*.asf; do
        [ -e "$asf" ] || continue
        for amc in "${asf%.asf}"_*.amc "${asf%.asf}".amc; do
            [ -e "$amc" ] || continue
            name=$(basename "$amc")
            [ -n "${done_names[$name]:-}" ] && continue
            done_names[$name]=1
            check "$name" --bone-ends "$asf" --motion "$amc"
        done
    done
done
echo "fbx readers: $checked files checked, $failed failed (readers: ${readers[*]})"
exit $((failed > 255 ? 255 : failed)) # an exit status is one byte
