#!/usr/bin/env bash
# Every file named on standard input through `bvhview info` (an .amc with the CMU skeleton of
# tests/data), on one core and under a 4 GB address-space limit, as issue 44 asks: how long each
# took and how it ended. Prints "milliseconds exit-code file", slowest first; exit codes other
# than 0 and 2 (a panic's 101, an abort's 134, a timeout's 124) are listed again at the end.
#   find DIR -type f -size -1024k | scripts/answer_times.sh [BVHVIEW]   (default target/release)
set -uo pipefail
cd "$(dirname "$0")/.."
cli=${1:-target/release/bvhview}
asf=tests/data/asf_amc/heiden_12.asf
results=$(while read -r file; do
    case "$file" in *.amc) args=("$asf" --motion "$file") ;; *) args=("$file") ;; esac
    start=$(date +%s%N)
    prlimit --as=4000000000 taskset -c 0 timeout 30 "$cli" info "${args[@]}" >/dev/null 2>&1
    code=$?
    echo "$(( ($(date +%s%N) - start) / 1000000 )) $code $file"
done | sort -rn)
echo "$results"
echo "$results" | awk '$2 != 0 && $2 != 2 { print "ended badly: " $0 }'
