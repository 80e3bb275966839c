#!/usr/bin/env bash
# Every file named on standard input through `bvhview info` (an .amc with the CMU skeleton of
# tests/data), on one core and under a 4 GB address-space limit, as issue 44 asks: how long each
# took, its peak memory and how it ended. Prints "milliseconds peak-KB exit-code line", slowest
# first; exit codes other than 0 and 2 (a panic's 101, an abort's 134, a timeout's 124) are
# listed again at the end, and the slowest answer and the largest peak last.
# Characters (issue 58) are lines of two or three words:
#   character FILE          `positions FILE --character FILE --vertices` (read, bound, skinned)
#   dress TAKE CHARACTER    `convert TAKE --character CHARACTER -o x.glb` (retargeted, written)
#   find DIR -type f -size -1024k | scripts/answer_times.sh [BVHVIEW]   (default target/release)
set -uo pipefail
cd "$(dirname "$0")/.."
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
