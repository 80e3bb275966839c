#!/usr/bin/env bash
# FBX out read by three readers nobody here wrote: assimp (Debian's libassimp, through
# check_assimp.cpp), three.js's FBXLoader (npm `three`, pinned in package.json, through
# check_three.mjs) and Blender 5.2's FBX importer (PyPI `bpy`, pinned here, through
# check_blender.py). Every take of tests/data (BVH, the ASF/AMC pair, FBX, glTF; and the whole
# corpus in ../shared/data when it is beside the checkout) is converted to FBX by bvhview, read
# by each reader, and compared by compare.py with what bvhview says of the source take: node
# tree, animation, duration, and every joint at frames 0, 1, N/2 and N-1 within 1e-4 of the
# figure's height. Each character of tests/data/characters, with its own take and with a walk
# put on it, is converted to FBX with its mesh, and Blender's deformed mesh is compared by
# compare_mesh.py with bvhview's skinning, each vertex within 1e-4 of the height.
#
# Usage: tests/fbx_readers/run_checks.sh [BVHVIEW] [WORKDIR]
# What a reader needs is installed when missing: as root, apt-get installs libassimp-dev,
# pkg-config and g++ (assimp) and nodejs and npm (three.js); npm installs three into
# ${CARGO_TARGET_DIR:-target}/tools/fbx-readers; a venv of Python 3.13 (python3.13, or pyenv's)
# with bpy and numpy from pip goes into its bpy/ (about 400 MB). BVHVIEW_BPY=/path/to/python
# uses a Python that has bpy 5.2.3 and numpy instead (nothing installed). A reader that cannot be
# set up is skipped with one line ("fbx readers: three.js: ...: skipped"). The last line is
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
# Blender: bpy (Blender 5.2 as a Python module, from PyPI) in a venv of Python 3.13 (the only
# Python bpy 5.2 is built for) in the tools folder; BVHVIEW_BPY=/path/to/python uses a Python
# that has bpy already (then nothing is installed). Python 3.13 is python3.13 on PATH, or
# pyenv's newest 3.13.
bpy_want=5.2.3
bpy_python=${BVHVIEW_BPY:-$tools/bpy/bin/python}
bpy_have() { "$bpy_python" -c 'import bpy, numpy; print(bpy.app.version_string.split()[0])' 2>/dev/null | tail -n 1; }
if [ -z "${BVHVIEW_BPY:-}" ] && [ "$(bpy_have)" != "$bpy_want" ]; then
    py313=
    if python3.13 -c '' 2>/dev/null; then
        py313=$(command -v python3.13)
    elif command -v pyenv >/dev/null; then
        version=$(pyenv versions --bare 2>/dev/null | grep -E '^3\.13(\.[0-9]+)?$' | sort -t. -k3 -n | tail -n 1)
        [ -n "$version" ] && py313=$(pyenv root)/versions/$version/bin/python3.13
    fi
    if [ -n "$py313" ] && [ -x "$py313" ]; then
        echo "installing: bpy==$bpy_want numpy into $tools/bpy (for the FBX reader checks; about 400 MB)"
        { [ -x "$tools/bpy/bin/python" ] || "$py313" -m venv "$tools/bpy"; } >"$work/bpy.log" 2>&1 \
            && "$tools/bpy/bin/python" -m pip install -q --disable-pip-version-check "bpy==$bpy_want" numpy \
                >>"$work/bpy.log" 2>&1
    else
        echo "no Python 3.13 (python3.13 on PATH, or pyenv install 3.13)" >"$work/bpy.log"
    fi
fi
bpy_version=$(bpy_have)
if [ "$bpy_version" = "$bpy_want" ]; then
    readers+=(blender)
elif [ -s "$work/bpy.log" ]; then
    skipped+=("blender: bpy $bpy_want could not be set up in $tools/bpy ($(tail -n 1 "$work/bpy.log"))")
else
    skipped+=("blender: $bpy_python has bpy ${bpy_version:-none}, not $bpy_want")
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
            blender) "$bpy_python" "$here/check_blender.py" "$w.fbx" "$frames" "${at[@]}" >"$w.blender.json" 2>"$w.blender.err" ;;
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

# Characters: the skinned mesh as a reader deforms it, against bvhview's own skinning
# (`positions --character CHAR --vertices`), at frames 0, 1, N/2 and N-1, by compare_mesh.py:
# each character file with its own take, and 20 frames of a walk put on it. The walk is cut
# first (convert --frames) and then put on the character, for the FBX and for the vertices
# alike: the retarget stands the feet on the floor over the frames it is given, and `positions
# --frames` picks frames after it, so `positions WALK --frames 0..20 --character` would stand
# 5 mm (capsule man) to 36 mm (Kenney) higher than `convert WALK --frames 0..20 --character`.
# Only Blender gives the mesh (assimp and three.js are not asked for it).
mesh_readers=()
for reader in "${readers[@]}"; do
    [ "$reader" = blender ] && mesh_readers+=(blender)
done
check_character() { # check_character NAME CHAR [INPUT]: INPUT's take (default CHAR's own) on CHAR
    local name=$1 char=$2 input=${3:-$2}
    local w=$work/$name
    checked=$((checked + 1))
    if ! "$cli" convert -q "$input" --character "$char" -o "$w.fbx" 2>"$w.err" \
        || ! "$cli" positions -q "$input" --character "$char" --vertices -o "$w.vertices.npy" 2>>"$w.err" \
        || ! "$cli" info "$w.fbx" >"$w.info" 2>>"$w.err"; then
        echo "$name: FAIL: bvhview: $(head -c 300 "$w.err")"
        failed=$((failed + 1))
        return
    fi
    local frames at=() dumps=()
    frames=$(awk '/^frames:/ { print $2 }' "$w.info")
    for f in 0 1 $((frames / 2)) $((frames - 1)); do
        [ "$f" -ge 0 ] && [ "$f" -lt "$frames" ] && [[ " ${at[*]} " != *" $f "* ]] && at+=("$f")
    done
    for reader in "${mesh_readers[@]}"; do
        case $reader in
            blender) "$bpy_python" "$here/check_blender.py" --mesh "$w.blender.npy" "$w.fbx" "$frames" "${at[@]}" \
                >"$w.blender.json" 2>"$w.blender.err" ;;
        esac
        dumps+=("$w.$reader.json")
    done
    if ! python3 "$here/compare_mesh.py" --vertices "$w.vertices.npy" --frames "$(IFS=,; echo "${at[*]}")" \
        "${dumps[@]}" >"$w.compare" 2>&1; then
        failed=$((failed + 1))
    fi
    sed "s/^/$name: /" "$w.compare"
}
if [ ${#mesh_readers[@]} -gt 0 ]; then
    walk=$root/tests/data/bvh/bvh11_131_01.bvh
    "$cli" convert -q "$walk" --frames 0..20 -o "$work/walk_0-20.bvh"
    for folder in "${folders[@]}"; do
        for char in "$folder"/characters/*.fbx "$folder"/characters/*.glb; do
            [ -e "$char" ] || continue
            name=$(basename "$char")
            [ -n "${done_names[character:$name]:-}" ] && continue
            done_names[character:$name]=1
            check_character "$name.own_take" "$char"
            check_character "$name.walk_0-20" "$char" "$work/walk_0-20.bvh"
        done
    done
fi
echo "fbx readers: $checked files checked, $failed failed (readers: ${readers[*]})"
exit $((failed > 255 ? 255 : failed)) # an exit status is one byte
