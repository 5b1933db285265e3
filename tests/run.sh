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
# each works in its own temporary folder), the longest first: each worker takes the next test not
# yet taken (a mkdir claims it), so the workers end together. A test's output is shown when it
# ends, whole (one worker prints at a time), with its line "== NAME: P passed, F failed (S s)".
jobs=${MOTE_TEST_JOBS:-2}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# run_one NAME CMD...: run one test into $work/NAME.{log,rc}, then show it and write its counts
# to $work/NAME.sum ("P F")
run_one() {
    name=$1
    shift
    start=$(date +%s)
    if [ "$limit" -gt 0 ]; then # (stdin: not the shard's list)
        timeout "$limit" "$@" >"$work/$name.log" 2>&1 </dev/null
    else
        "$@" >"$work/$name.log" 2>&1 </dev/null
    fi
    rc=$?
    secs=$(($(date +%s) - start))
    {
        [ "$limit" -gt 0 ] && [ "$rc" -eq 124 ] &&
            echo "$name: stopped after $limit s (the time limit: a hang?)"
        line=$(grep -E '^[0-9]+ passed, [0-9]+ failed' "$work/$name.log" | tail -n 1)
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
        echo "$p $f" >"$work/$name.sum"
        echo "== $name: $p passed, $f failed ($secs s)"
    } >>"$work/$name.log"
    until mkdir "$work/print.lock" 2>/dev/null; do sleep 0.1; done
    cat "$work/$name.log"
    rmdir "$work/print.lock"
}
# the tests (programs, then scripts), and the order they are started in: the long ones first
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
long="test_charging.sh test_charging test_structure test_measure test_sep_dem test_sep_mesh
      test_mbevent test_python.sh test_mpi.sh test_live.sh test_fuzz test_separator.sh
      test_galactica.sh test_readers.sh test_nbody.sh test_hardening.sh test_progress.sh test_bem
      test_nbody test_separator test_field test_vocabulary.sh test_ensemble.sh
      test_script_limits.sh"
order=""
for n in $long; do
    case " $all " in *" $n "*) order="$order $n" ;; esac
done
for n in $all; do
    case " $order " in *" $n "*) ;; *) order="$order $n" ;; esac
done
s=0
while [ "$s" -lt "$jobs" ]; do
    (
        for n in $order; do
            mkdir "$work/$n.taken" 2>/dev/null || continue
            case "$n" in
            *.sh) run_one "$n" sh "tests/$n" "$build" ;;
            *) run_one "$n" "$build/tests/$n" ;;
            esac
        done
    ) &
    s=$((s + 1))
done
wait
for name in $all; do
    set -- $(cat "$work/$name.sum" 2>/dev/null || echo "0 1")
    total_pass=$((total_pass + $1))
    total_fail=$((total_fail + $2))
    [ "$2" -ne 0 ] && bad="$bad $name"
done
[ -n "$bad" ] && echo "failing:$bad"
echo "$total_pass passed, $total_fail failed"
[ "$total_fail" -eq 0 ]
