#!/bin/bash
# Blender's own import of every FBX and glTF test file against bvhview's reading of it (see
# check_import.py). Usage:
#   bash tests/blender/run_import_checks.sh [BVHVIEW] [WORKDIR]
# A file Blender imports without an armature (ufbx's animated cubes), or that Blender 3.4's
# importer cannot read, is skipped with a note. The last line is
# "import checks: N failed: F skipped: S"; the exit status is F.
set -u
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
B=${1:-$ROOT/target/debug/bvhview}
W=${2:-/tmp/blenderimport}
mkdir -p "$W"
D=$ROOT/tests/data
checked=0
fails=0
skipped=0
for file in "$D"/fbx/*.fbx "$D"/gltf/*.glb "$D"/gltf/*.gltf "$D"/fbx/ufbx/*.fbx; do
  name=$(basename "$file")
  if ! "$B" positions -q "$file" -o "$W/$name.csv" 2>"$W/$name.err"; then
    echo "== $name: bvhview reads no take ($(cat "$W/$name.err")): skipped"
    skipped=$((skipped+1))
    continue
  fi
  ft=$("$B" info "$file" 2>/dev/null | awk '/^frame time:/ {print $3}')
  echo "== $name"
  blender -b --factory-startup --python-exit-code 3 --python "$HERE/check_import.py" -- "$file" "$W/$name.csv" "$ft" \
    >"$W/$name.log" 2>&1
  status=$?
  grep -E '^(height|worst|PASS|FAIL|check_import|Traceback)' "$W/$name.log"
  case $status in
    0) checked=$((checked+1)) ;;
    1|3) checked=$((checked+1)); fails=$((fails+1)) ;;
    *) echo "   skipped: Blender's import has nothing to compare (see $W/$name.log)"
       skipped=$((skipped+1)) ;;
  esac
done
echo "import checks: $checked failed: $fails skipped: $skipped"
exit $fails
