#!/bin/sh
# run.sh BUILD_DIR: run every test program (BUILD_DIR/tests/test_*) and test script
# (tests/test_*.sh, given BUILD_DIR), show their output, and finish with one summary line
# "N passed, M failed" over all of them. Exits non-zero if any check or program failed.
# Each program gets at most MOTE_TEST_TIMEOUT seconds (default 600, about 15 times the slowest
# under the sanitizers; none with MOTE_SLOW; 0 = none), so a hang fails instead of running on.
set -u
if [ -n "${MOTE_SLOW:-}" ]; then
    limit=${MOTE_TEST_TIMEOUT:-0}
else
    limit=${MOTE_TEST_TIMEOUT:-600}
fi
command -v timeout >/dev/null 2>&1 || limit=0
build=${1:-build}
here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/.." && pwd)
cd "$top" || exit 1
total_pass=0
total_fail=0
bad=""
log=$(mktemp)
run_one() {
    name=$1
    shift
    start=$(date +%s)
    if [ "$limit" -gt 0 ]; then
        timeout "$limit" "$@" >"$log" 2>&1
    else
        "$@" >"$log" 2>&1
    fi
    rc=$?
    end=$(date +%s)
    cat "$log"
    [ "$limit" -gt 0 ] && [ "$rc" -eq 124 ] &&
        echo "$name: stopped after $limit s (the time limit: a hang?)"
    line=$(grep -E '^[0-9]+ passed, [0-9]+ failed' "$log" | tail -n 1)
    if [ -n "$line" ]; then
        p=$(echo "$line" | sed -E 's/^([0-9]+) passed.*/\1/')
        f=$(echo "$line" | sed -E 's/^[0-9]+ passed, ([0-9]+) failed.*/\1/')
    else
        p=0
        f=1
        echo "$name: no summary line (crashed?)"
    fi
    if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then
        f=1
        echo "$name: exit status $rc"
    fi
    total_pass=$((total_pass + p))
    total_fail=$((total_fail + f))
    [ "$f" -ne 0 ] && bad="$bad $name"
    echo "== $name: $p passed, $f failed ($((end - start)) s)"
}
for t in "$build"/tests/test_*; do
    [ -x "$t" ] || continue
    run_one "$(basename "$t")" "$t"
done
for s in tests/test_*.sh; do
    [ -f "$s" ] || continue
    run_one "$(basename "$s")" sh "$s" "$build"
done
rm -f "$log"
[ -n "$bad" ] && echo "failing:$bad"
echo "$total_pass passed, $total_fail failed"
[ "$total_fail" -eq 0 ]
