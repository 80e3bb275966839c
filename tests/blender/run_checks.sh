#!/bin/bash
# Convert each test file to .glb with bvhview and check it in Blender at
# frames 0, 1, N/2 and N-1 (see check_gltf.py): once as is, and once converted
# with --skin, which also checks the skinned mesh as Blender deforms it. Usage:
#   bash tests/blender/run_checks.sh [BVHVIEW] [WORKDIR]
# The last line is "files checked: N failed: F" (N .glb files, two per take);
# the exit status is F.
set -u
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
B=${1:-$ROOT/target/debug/bvhview}
W=${2:-/tmp/blendercheck}
mkdir -p "$W"
D=$ROOT/tests/data
checked=0
fails=0

check() {   # check GLB CSV FLAGS... -- FRAMES...
  local glb=$1 csv=$2; shift 2
  checked=$((checked+1))
  blender -b --factory-startup --python "$HERE/check_gltf.py" -- "$glb" "$csv" "$@" 2>&1 |
    grep -E '^(frame|skin|PASS|FAIL|height|time|worst|imported|scene|note|check_gltf|Traceback|  )'
  [ "${PIPESTATUS[0]}" = 0 ] || fails=$((fails+1))
}

run() {   # run NAME BONE_ENDS INPUT...
  local name=$1 ends=$2; shift 2
  local n ft
  n=$("$B" info "$@" | awk '/^frames:/ {print $2}')
  ft=$("$B" info "$@" | awk '/^frame time:/ {print $3}')
  "$B" positions -q "$@" -o "$W/$name.csv"
  # Rest pose: a copy of the BVH with no frames (ASF: no --motion).
  if [ "$ends" = yes ]; then
    "$B" positions -q "$1" -o "$W/$name.rest.csv"
  else
    python3 - "$1" "$W/$name.rest.bvh" "$ft" <<'PY'
import sys, re
text = open(sys.argv[1], newline="").read()
head = re.split(r"MOTION", text, maxsplit=1)[0]
open(sys.argv[2], "w").write(head + "MOTION\nFrames: 0\nFrame Time: %s\n" % sys.argv[3])
PY
    "$B" positions -q "$W/$name.rest.bvh" -o "$W/$name.rest.csv"
  fi
  local flags=(--frame-time "$ft" --rest "$W/$name.rest.csv")
  [ "$ends" = yes ] && flags+=(--bone-ends)
  local frames=(0 1 $((n/2)) $((n-1)))
  echo "== $name: $n frames, frame time $ft"
  if "$B" convert -q "$@" -o "$W/$name.glb"; then
    check "$W/$name.glb" "$W/$name.csv" "${flags[@]}" "${frames[@]}"
  else
    checked=$((checked+1)); fails=$((fails+1))
  fi
  echo "== $name --skin"
  if "$B" convert -q "$@" -o "$W/$name.skin.glb" --skin; then
    check "$W/$name.skin.glb" "$W/$name.csv" "${flags[@]}" --skin "${frames[@]}"
  else
    checked=$((checked+1)); fails=$((fails+1))
  fi
}

run bvh11_131_01 no $D/bvh/bvh11_131_01.bvh
run opencollar_run no $D/bvh/opencollar_run.bvh
run makehuman_walk1 no $D/bvh/makehuman_walk1.bvh
run bvhpython_test_freebvh no $D/bvh/bvhpython_test_freebvh.bvh
run heiden_12_02_01 yes $D/asf_amc/heiden_12.asf --motion $D/asf_amc/heiden_12_02_01.amc
echo "files checked: $checked failed: $fails"
exit $fails
