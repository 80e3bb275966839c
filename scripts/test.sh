#!/usr/bin/env bash
# Installs what the tests need (Debian packages when run as root), then runs every test: cargo's,
# then the Python package's pytest suite (python/). The README's test command; .ci/run calls it too.
set -euo pipefail
cd "$(dirname "$0")/.."

# Debian packages the tests use: OSMesa for offscreen pictures, the X11/GL libraries the window
# loads at run time, Xvfb, xdotool and xwd for the end-to-end window test, and g++ for the
# article's own program, rebuilt from its text (tests/article/article_program_rebuilt.rs, with ../shared), and
# for OpenH264's C++ (the `video` feature). nasm adds OpenH264's assembly (faster; the build
# works without it). ffmpeg checks the MP4s bvhview writes (tests/render/video_mp4.rs): a checker only,
# bvhview never runs it.
PACKAGES=(
    libosmesa6
    libx11-6 libx11-xcb1 libxcb1 libxcursor1 libxi6 libxkbcommon-x11-0
    libgl1 libglx-mesa0 libgl1-mesa-dri libegl1 libegl-mesa0
    xvfb xauth xdotool x11-apps opencc g++ nasm ffmpeg
)

missing=()
for package in "${PACKAGES[@]}"; do
    dpkg -s "$package" >/dev/null 2>&1 || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        echo "installing: ${missing[*]}"
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
    else
        echo "missing Debian packages: ${missing[*]} (run as root, or: sudo apt-get install ${missing[*]})" >&2
        exit 1
    fi
fi

# The repository's own data (tests/data, tests/oracle, tests/edge) is always tested. The whole
# corpus beside the checkout (../shared/data, as in CI) adds the tests marked #[ignore] for it.
test_args=()
if [ -d ../shared/data ]; then
    echo "../shared/data is present: also running the whole-corpus tests"
    test_args=(--include-ignored)
else
    echo "../shared/data is absent: testing with the repository's own data (tests/data); the whole-corpus tests are skipped"
fi

# One clean build, not an edited one: incremental caches would double the disk the build needs.
export CARGO_INCREMENTAL=0

log=$(mktemp)
trap 'rm -f "$log"' EXIT
status=0
# --show-output: the golden-picture tests print how many pixels drifted even when they pass.
cargo test --all-targets --locked --no-fail-fast -- --show-output "${test_args[@]}" 2>&1 | tee "$log" || status=$?
# The examples in the docs (`--all-targets` leaves doctests out).
cargo test --doc --locked --no-fail-fast 2>&1 | tee -a "$log" || status=$?
# The builds without the default features that matter: the library and CLI with neither the
# window, FBX nor glTF, and with FBX alone (the tests drive the command, so `cli` stays on).
# Tests that need a feature say so (Cargo.toml, `#[cfg(feature = …)]`); the rest run on each
# build. The library alone, without the command's crates (clap, signal-hook), is built too.
# Their own target folder: the binary the checks below run (pytest, the glTF validator) stays
# the one with every feature.
features_target="${CARGO_TARGET_DIR:-target}/features"
# The benchmarks and the fuzz targets are not run here (speed lives in `bench`; fuzzing in
# scripts/fuzz.sh), but they must keep compiling against the library.
echo "cargo check -p bvhview-bench"
cargo check -p bvhview-bench --locked 2>&1 | tee -a "$log" || status=$?
echo "cargo check (fuzz targets)"
cargo check --manifest-path fuzz/Cargo.toml --bins --locked --target-dir "${CARGO_TARGET_DIR:-target}" 2>&1 | tee -a "$log" || status=$?
echo "cargo build --lib --no-default-features"
cargo build --lib --no-default-features --locked --target-dir "$features_target" 2>&1 | tee -a "$log" || status=$?
for features in "--no-default-features --features cli" "--no-default-features --features cli,fbx"; do
    echo "cargo test $features"
    # shellcheck disable=SC2086
    cargo test $features --locked --no-fail-fast --target-dir "$features_target" 2>&1 | tee -a "$log" || status=$?
    # Each build is a full set of test programs: gone before the next, so the disk holds two, not three.
    rm -rf "$features_target"
done
grep '^drift ' "$log" | awk '{ if ($3 > 0) n++ } END { printf "golden pictures: %d compared, %d with any pixel drift\n", NR, n }' || true
# Machines differ: say whether the AVX-512 row reader was compared with the plain one here.
grep -m1 '^row reader: ' "$log" || echo "row reader: the AVX-512 check did not run"
# One closing line for the whole run: the sum over every test binary.
summary=$(awk '/^test result:/ { p += $4; f += $6; i += $8 } END { printf "%d %d %d", p, f, i }' "$log")
read -r passed failed ignored <<<"$summary"

# The Python package: pip installs pytest's needs and the package (built by maturin with the
# pinned pyo3/numpy crates), then pytest compares it with the CLI just built. As root pip installs
# for the whole interpreter; otherwise for the user.
python=${PYTHON:-python3}
python_needs=(maturin==1.16.0 pytest==9.2.0 numpy==2.4.6 mypy==2.4.1 pandas==3.1.1 pyarrow==26.0.1
    "dask[distributed]==2026.8.0" pybvh-ml==0.6.0 pybvh==0.8.2 bvhio==1.5.4)
pip_scope=()
[ "$(id -u)" = 0 ] || pip_scope=(--user)
pylog=$(mktemp)
trap 'rm -f "$log" "$pylog"' EXIT
python_failed=0
if ! command -v "$python" >/dev/null; then
    echo "python: $python not found: the Python package needs Python 3.11 with pip (or set PYTHON)" >&2
    python_failed=1
elif ! "$python" -m pip --version >/dev/null 2>&1; then
    echo "python: '$python -m pip' is not available: install pip for $python (Debian: apt-get install python3-pip), or set PYTHON to a Python with pip" >&2
    python_failed=1
elif ! "$python" -m pip install -q --disable-pip-version-check "${pip_scope[@]}" "${python_needs[@]}"; then
    echo "python: pip could not install ${python_needs[*]}" >&2
    python_failed=1
# The crate's build shares the root's target folder; no build isolation: maturin is installed.
elif ! CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/target}" "$python" -m pip install -q --disable-pip-version-check \
        "${pip_scope[@]}" --no-build-isolation --no-deps --force-reinstall ./python; then
    echo "python: building and installing the package (pip install ./python) failed" >&2
    python_failed=1
else
    # The CLI cargo test has just built: pytest compares the package with it.
    cli="${CARGO_TARGET_DIR:-target}/debug/bvhview"
    [ -x "$cli" ] && export BVHVIEW_CLI="$cli"
    "$python" -m pytest python/tests -q -rs 2>&1 | tee "$pylog" || python_failed=1
fi
# pytest's closing line: "3 failed, 86 passed, 1 skipped, 2 errors in 1.2s" (any order).
read -r py_passed py_failed py_skipped <<<"$(tail -n 1 "$pylog" | awk '{
    for (k = 2; k <= NF; k++) {
        word = $k; sub(/,$/, "", word)
        if (word == "passed") p = $(k - 1)
        if (word == "failed" || word == "error" || word == "errors") f += $(k - 1)
        if (word == "skipped") s = $(k - 1)
    }
} END { printf "%d %d %d", p, f, s }')"
if [ "$python_failed" -ne 0 ] && [ "$py_failed" -eq 0 ]; then
    py_failed=1  # the package did not build or pytest did not finish: count it, not silence it
fi
echo "pytest: $py_passed passed, $py_failed failed, $py_skipped skipped"
passed=$((passed + py_passed))
failed=$((failed + py_failed))
ignored=$((ignored + py_skipped))
[ "$python_failed" -eq 0 ] || status=1

# Independent consumers of the glTF export. The Khronos validator (node; installed when missing)
# checks every corpus take; each file counts as a test. Blender is large and is not installed
# here: when it is present, it imports five takes and compares joint positions, and checks the
# convert edits Blender's importer can also make (tests/blender).
cli="${CARGO_TARGET_DIR:-target}/debug/bvhview"
gltf_log=$(mktemp)
trap 'rm -f "$log" "$pylog" "$gltf_log"' EXIT
scripts/check_gltf.sh "$cli" >"$gltf_log" 2>&1 || status=1
grep -v ': 0 errors' "$gltf_log" || true
read -r gltf_files gltf_failed <<<"$(awk '/^gltf-validator:/ { print $2, $4 }' "$gltf_log")"
gltf_files=${gltf_files:-0}
gltf_failed=${gltf_failed:-1}
passed=$((passed + gltf_files - gltf_failed))
failed=$((failed + gltf_failed))
if command -v blender >/dev/null; then
    blender_log=$(mktemp)
    bash tests/blender/run_checks.sh "$cli" "$(mktemp -d)" 2>&1 | tee "$blender_log" || status=1
    read -r blender_checked blender_failed <<<"$(awk '/^files checked:/ { print $3, $5 }' "$blender_log")"
    echo "blender: ${blender_checked:-0} files checked, ${blender_failed:-1} failed"
    passed=$((passed + ${blender_checked:-0} - ${blender_failed:-0}))
    failed=$((failed + ${blender_failed:-1}))
    # convert's edits against the same operations in Blender's BVH importer.
    # FBX and glTF test files: Blender's own import against bvhview's reading.
    bash tests/blender/run_import_checks.sh "$cli" "$(mktemp -d)" 2>&1 | tee "$blender_log" || status=1
    read -r import_checked import_failed <<<"$(awk '/^import checks:/ { print $3, $5 }' "$blender_log")"
    echo "blender: ${import_checked:-0} FBX/glTF imports checked, ${import_failed:-1} failed"
    passed=$((passed + ${import_checked:-0} - ${import_failed:-0}))
    failed=$((failed + ${import_failed:-1}))
    bash tests/blender/run_edit_checks.sh "$cli" "$(mktemp -d)" 2>&1 | tee "$blender_log" || status=1
    read -r edit_checks edit_failed <<<"$(awk '/^edit checks:/ { print $3, $5 }' "$blender_log")"
    echo "blender: ${edit_checks:-0} edit checks, ${edit_failed:-1} failed"
    passed=$((passed + ${edit_checks:-0} - ${edit_failed:-0}))
    failed=$((failed + ${edit_failed:-1}))
    rm -f "$blender_log"
else
    echo "blender: not installed, the Blender import check is skipped (apt-get install blender python3-numpy)"
    ignored=$((ignored + 1))
fi
# Independent readers of the FBX export: assimp (libassimp, apt-get), three.js's FBXLoader (npm,
# into the target folder's tools/fbx-readers) and Blender's importer (bpy from pip, in a Python 3.13
# venv there, or BVHVIEW_BPY=python) read every corpus take converted to FBX, and Blender the
# characters' meshes, each file a test (tests/fbx_readers/run_checks.sh); a reader that cannot be
# installed is skipped, one line.
fbx_log=$(mktemp)
trap 'rm -f "$log" "$pylog" "$gltf_log" "$fbx_log"' EXIT
bash tests/fbx_readers/run_checks.sh "$cli" >"$fbx_log" 2>&1 || status=1
grep -E 'FAIL|skipped|^fbx readers:' "$fbx_log" || true
read -r fbx_checked fbx_failed <<<"$(awk '/^fbx readers: [0-9]+ files checked/ { print $3, $6 }' "$fbx_log")"
fbx_checked=${fbx_checked:-0}
fbx_failed=${fbx_failed:-1} # no closing line: the script itself failed
passed=$((passed + fbx_checked - fbx_failed))
failed=$((failed + fbx_failed))
ignored=$((ignored + $(grep -c '^fbx readers: .*: skipped$' "$fbx_log" || true)))
# The docs build without a warning, public and private items (TEACHING.md links the private
# process_* functions); each build counts as a test.
for doc_args in "--no-deps" "--no-deps --document-private-items"; do
    # shellcheck disable=SC2086
    if RUSTDOCFLAGS="-D warnings" cargo doc --locked $doc_args >/dev/null 2>"$log"; then
        echo "cargo doc $doc_args: no warnings"
        passed=$((passed + 1))
        # Every public type of the library's docs shows an example (one check).
        if [ "$doc_args" = "--no-deps" ]; then
            if python3 scripts/doc_examples.py "${CARGO_TARGET_DIR:-target}/doc/bvhview"; then
                passed=$((passed + 1))
            else
                failed=$((failed + 1))
                status=1
            fi
        fi
    else
        cat "$log" >&2
        echo "cargo doc $doc_args: failed" >&2
        failed=$((failed + 1))
        status=1
    fi
done
# No two modules of src/ use each other, however indirectly (one check).
if python3 scripts/import_graph.py --quiet; then
    passed=$((passed + 1))
else
    failed=$((failed + 1))
    status=1
fi
echo "all tests: $passed passed, $failed failed, $ignored ignored"
if [ "$passed" -eq 0 ]; then
    echo "no test ran" >&2
    exit 1
fi
exit "$status"
