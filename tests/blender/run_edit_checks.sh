#!/bin/bash
# `bvhview convert` edits checked against the same operation in Blender's BVH importer (see
# check_edits.py): each check must PASS, and each deliberately wrong one must FAIL. Usage:
#   bash tests/blender/run_edit_checks.sh [BVHVIEW] [WORKDIR]
# Last line: "edit checks: N failed: F"; the exit status is F.
set -u
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
B=${1:-$ROOT/target/debug/bvhview}
W=${2:-/tmp/blender-edits}
mkdir -p "$W"
D=$ROOT/tests/data/bvh
checks=0
fails=0

# check EXPECT ORIGINAL EDITED KIND [ARG]: EXPECT is pass or fail.
check() {
  local expect=$1
  shift
  checks=$((checks + 1))
  local line
  line=$(blender -b --factory-startup --python "$HERE/check_edits.py" -- "$@" 2>&1 |
    grep -E '^(PASS|FAIL)' | tail -n 1)
  local got=${line%%:*}
  if [ "${got,,}" = "$expect" ]; then
    echo "ok ($expect expected) $(basename "$1") $(basename "$2"): $line"
  else
    fails=$((fails + 1))
    echo "WRONG (expected $expect) $(basename "$1") $(basename "$2"): ${line:-no verdict}"
  fi
}

free=$D/bvhpython_test_freebvh.bvh
run=$D/opencollar_run.bvh
cmu=$D/bvh11_131_01.bvh
walk=$D/makehuman_walk1.bvh
"$B" convert -q "$free" --scale 1.7 -o "$W/free_scale.bvh"
check pass "$free" "$W/free_scale.bvh" scale 1.7
check fail "$free" "$W/free_scale.bvh" scale 1.69
"$B" convert -q "$free" --out-up z -o "$W/free_up_z.bvh"
check pass "$free" "$W/free_up_z.bvh" up-z
"$B" convert -q "$run" --out-up z -o "$W/run_up_z.bvh"
check pass "$run" "$W/run_up_z.bvh" up-z
"$B" convert -q "$walk" --out-up y -o "$W/walk_up_y.bvh"
check pass "$walk" "$W/walk_up_y.bvh" up-y
check fail "$walk" "$W/walk_up_y.bvh" up-z
"$B" convert -q "$run" --frames 5..20 -o "$W/run_frames.bvh"
check pass "$run" "$W/run_frames.bvh" frames 5
check fail "$run" "$W/run_frames.bvh" frames 6
"$B" convert -q "$run" --fps 15 -o "$W/run_fps.bvh"
check pass "$run" "$W/run_fps.bvh" fps 2
"$B" convert -q "$cmu" --fps 40 -o "$W/cmu_fps.bvh"
check pass "$cmu" "$W/cmu_fps.bvh" fps 3
check fail "$cmu" "$W/cmu_fps.bvh" fps 2
echo "edit checks: $checks failed: $fails"
exit $fails
