#!/bin/sh
# run.sh BUILD_DIR: run every test program (BUILD_DIR/tests/test_*) and test script
# (tests/test_*.sh, given BUILD_DIR), show their output, and finish with one summary line
# "N passed, M failed" over all of them. Exits non-zero if any check or program failed. They run
# MOTE_TEST_JOBS at a time (default 2); MOTE_TEST_SKIP names tests not to run (the sanitized
# pass's list, Makefile).
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
# The tests run MOTE_TEST_JOBS at a time (default 2: CI's cores; every test holds under load, and
# each works in its own temporary folder), the longest first; their outputs are shown in the
# usual order when all have ended.
jobs=${MOTE_TEST_JOBS:-2}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# run_one NAME CMD...: run one test into $work/NAME.{log,rc,secs}
run_one() {
    name=$1
    shift
    start=$(date +%s)
    if [ "$limit" -gt 0 ]; then # (stdin: not the shard's list)
        timeout "$limit" "$@" >"$work/$name.log" 2>&1 </dev/null
    else
        "$@" >"$work/$name.log" 2>&1 </dev/null
    fi
    echo $? >"$work/$name.rc"
    echo $(($(date +%s) - start)) >"$work/$name.secs"
}
# the tests in their usual order (programs, then scripts), and the order they are started in:
# the long ones first, so that the shards end together
all=""
skip=" ${MOTE_TEST_SKIP:-} "
for t in "$build"/tests/test_*; do
    case "$skip" in *" $(basename "$t") "*) continue ;; esac
    [ -x "$t" ] && all="$all $(basename "$t")"
done
for s in tests/test_*.sh; do
    case "$skip" in *" $(basename "$s") "*) continue ;; esac
    [ -f "$s" ] && all="$all $(basename "$s")"
done
[ -n "${MOTE_TEST_SKIP:-}" ] && echo "not run here (MOTE_TEST_SKIP):${MOTE_TEST_SKIP}"
long="test_galactica.sh test_nbody.sh test_nbody test_live.sh test_sep_dem test_structure
      test_fuzz test_charging.sh test_mbevent test_measure test_charging test_progress.sh
      test_mpi.sh test_separator.sh test_ensemble.sh"
order=""
for n in $long; do
    case " $all " in *" $n "*) order="$order $n" ;; esac
done
for n in $all; do
    case " $order " in *" $n "*) ;; *) order="$order $n" ;; esac
done
k=0
for n in $order; do
    echo "$n" >>"$work/shard.$((k % jobs))"
    k=$((k + 1))
done
s=0
while [ "$s" -lt "$jobs" ]; do
    if [ -f "$work/shard.$s" ]; then
        (
            while read -r n; do
                case "$n" in
                *.sh) run_one "$n" sh "tests/$n" "$build" ;;
                *) run_one "$n" "$build/tests/$n" ;;
                esac
            done <"$work/shard.$s"
        ) &
    fi
    s=$((s + 1))
done
wait
for name in $all; do
    log="$work/$name.log"
    rc=$(cat "$work/$name.rc" 2>/dev/null || echo 1)
    cat "$log" 2>/dev/null
    [ "$limit" -gt 0 ] && [ "$rc" -eq 124 ] &&
        echo "$name: stopped after $limit s (the time limit: a hang?)"
    line=$(grep -E '^[0-9]+ passed, [0-9]+ failed' "$log" 2>/dev/null | tail -n 1)
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
    echo "== $name: $p passed, $f failed ($(cat "$work/$name.secs" 2>/dev/null || echo '?') s)"
done
[ -n "$bad" ] && echo "failing:$bad"
echo "$total_pass passed, $total_fail failed"
[ "$total_fail" -eq 0 ]
