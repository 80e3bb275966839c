#!/usr/bin/env bash
# Installs what the tests need (Debian packages when run as root), then runs every test.
# The README's test command; .ci/run calls it too.
set -euo pipefail
cd "$(dirname "$0")/.."

# Debian packages the tests use: OSMesa for offscreen pictures, the X11/GL libraries the window
# loads at run time, and Xvfb, xdotool and xwd for the end-to-end window test.
PACKAGES=(
    libosmesa6
    libx11-6 libx11-xcb1 libxcb1 libxcursor1 libxi6 libxkbcommon-x11-0
    libgl1 libglx-mesa0 libgl1-mesa-dri libegl1 libegl-mesa0
    xvfb xauth xdotool x11-apps
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

log=$(mktemp)
trap 'rm -f "$log"' EXIT
status=0
# --show-output: the golden-picture tests print how many pixels drifted even when they pass.
cargo test --all-targets --locked --no-fail-fast -- --show-output "${test_args[@]}" 2>&1 | tee "$log" || status=$?
grep '^drift ' "$log" | awk '{ if ($3 > 0) n++ } END { printf "golden pictures: %d compared, %d with any pixel drift\n", NR, n }' || true
# One closing line for the whole run: the sum over every test binary.
summary=$(awk '/^test result:/ { p += $4; f += $6; i += $8 } END { printf "%d %d %d", p, f, i }' "$log")
read -r passed failed ignored <<<"$summary"
echo "all tests: $passed passed, $failed failed, $ignored ignored"
if [ "$passed" -eq 0 ]; then
    echo "no test ran" >&2
    exit 1
fi
exit "$status"
