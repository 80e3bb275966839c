#!/usr/bin/env bash
# Fuzz one loader with AFL++ through cargo-afl (stable Rust).
#   scripts/fuzz.sh bvh|asf|amc [EXECUTIONS] [WORKDIR]      (default 10000000, /tmp/bvhview-fuzz)
# Seeds come from the repository's corpus (tests/data) at run time (files up to 4 KB whole, the first 2 KB of larger
# ones, cut at a line end: small inputs run faster) and are
# written under WORKDIR, never into the project. Crashes land in WORKDIR/TARGET/out/default/crashes.
set -euo pipefail
cd "$(dirname "$0")/.."
target=${1:?usage: scripts/fuzz.sh bvh|asf|amc [EXECUTIONS] [WORKDIR]}
executions=${2:-10000000}
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
    *) echo "unknown target $target" >&2; exit 2 ;;
esac
find "$work/in" -size 0 -delete

AFL_SKIP_CPUFREQ=1 AFL_I_DONT_CARE_ABOUT_MISSING_CRASHES=1 AFL_NO_UI=1 AFL_NO_AFFINITY=1 \
    cargo afl fuzz -i "$work/in" -o "$work/out" -E "$executions" -t 1000 "fuzz/target/release/$target" \
    > "$work/afl.log" 2>&1 || true
stats="$work/out/default/fuzzer_stats"
echo "$target: $(grep -E '^execs_done' "$stats" | tr -s ' ') ; $(grep -E '^saved_crashes' "$stats" | tr -s ' ') ; $(grep -E '^saved_hangs' "$stats" | tr -s ' ')"
