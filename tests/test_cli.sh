#!/bin/sh
# test_cli.sh: the `mote` program end to end (spec 7): scripts run in a temporary directory and
# their exit status, messages and files are checked. Bad scripts (unknown command, arity, types,
# `compress`, missing files, ...) must fail validation with "FILE:LINE:COL: error:", exit
# status 1 and no file written, even by a `save` placed before the bad line; a runtime error
# exits with 2 and keeps the files of earlier commands; the original document's examples pass
# validation and a scaled-down equivalent runs; help and --version; the status line.
# Usage: sh tests/test_cli.sh BUILD_DIR   (uses BUILD_DIR/mote)
# Prints "ok - ..." or "FAIL - ..." per check and finally "N passed, M failed".

BUILD=${1:-build}
case "$BUILD" in
/*) ;;
*) BUILD="$(pwd)/$BUILD" ;;
esac
MOTE="$BUILD/mote"

passed=0
failed=0
ok() {
    passed=$((passed + 1))
    echo "ok - $1"
}
not_ok() {
    failed=$((failed + 1))
    echo "FAIL - $1"
    if [ -n "$2" ]; then
        printf '%s\n' "$2" | sed 's/^/    /'
    fi
}

if [ ! -x "$MOTE" ]; then
    not_ok "the program $MOTE exists"
    echo "$passed passed, $failed failed"
    exit 1
fi

T=$(mktemp -d /tmp/mote_test_cli.XXXXXX) || exit 1
trap 'rm -rf "$T"' EXIT
trap 'rm -rf "$T"; exit 1' INT TERM
n=0

# new_case: a fresh empty directory $D for one script; output goes to $T/out.$n, $T/err.$n
new_case() {
    n=$((n + 1))
    D="$T/case$n"
    mkdir "$D"
    OUT="$T/out.$n"
    ERR="$T/err.$n"
}

# run_mote ARGS...: run in $D, set $rc
run_mote() {
    (cd "$D" && "$MOTE" "$@" >"$OUT" 2>"$ERR")
    rc=$?
}

# files_in_case: the names in $D other than the given inputs, one line
files_in_case() {
    (cd "$D" && ls -A) | grep -v -x -F -e s.mote "$@" | tr '\n' ' '
}

# expect_invalid DESC SCRIPT_TEXT PATTERN...: validation must fail: exit 1, stderr has
# every pattern (fixed strings), no file written. Extra input files may be placed in $D by the
# caller through $INPUTS (names) before calling.
expect_invalid() {
    desc=$1
    text=$2
    shift 2
    new_case
    for f in $INPUTS; do cp "$T/$f" "$D/$f"; done
    printf '%s' "$text" >"$D/s.mote"
    run_mote run s.mote
    if [ "$rc" -eq 1 ]; then ok "$desc: exit status 1"; else not_ok "$desc: exit status 1" "got $rc; stderr: $(cat "$ERR")"; fi
    missing=""
    for p in "$@"; do
        grep -q -F -e "$p" "$ERR" || missing="$missing [$p]"
    done
    if [ -z "$missing" ]; then ok "$desc: message"; else not_ok "$desc: message" "lacks$missing in: $(cat "$ERR")"; fi
    extra=$(files_in_case $(for f in $INPUTS; do printf -- '-e %s ' "$f"; done))
    if [ -z "$extra" ]; then ok "$desc: no file written"; else not_ok "$desc: no file written" "found: $extra"; fi
    # nothing ran: not even the seeding report or a status line on stdout
    if [ -s "$OUT" ]; then not_ok "$desc: nothing ran" "$(cat "$OUT")"; else ok "$desc: nothing ran"; fi
}

INPUTS=""

# ---- validation errors -------------------------------------------------------------------------

expect_invalid "unknown command" 'new 2 0.4
save early.state
frobnicate 3
' "s.mote:3:1: error:" "unknown command" "frobnicate"

expect_invalid "compressl with 4 numbers (the original document's example)" 'new 2 0.4
save early.state
compressl 0.49 0.503423 0.000001 10
' "s.mote:3:34: error:" "too many arguments" "compress_left_wall eta dLmax K"

expect_invalid "too few arguments" 'new 2
' "s.mote:1:1: error:" "too few arguments"

expect_invalid "step 1e3 is not an integer" 'new 2 0.4
save early.state
step 1e3
' "s.mote:3:6: error:" "expected an integer" "1e3"

expect_invalid "bad real number" 'new 2 0.4x
' "s.mote:1:7: error:" "expected a real number" "0.4x"

expect_invalid "decimal comma" 'new 2 0,4
' "s.mote:1:7: error:" "expected a real number"

expect_invalid "compress names the three variants" 'new 2 0.4
save early.state
compress 0.45 0.1 1
' "s.mote:3:1: error:" "compress_left_wall" "compress_right_wall" "compress_two_walls"

expect_invalid "load of a missing file" 'new 2 0.4
save early.state
load nosuch.state
' "s.mote:3:" "error:" "nosuch.state"

expect_invalid "unterminated quote" 'new 2 0.4
save "early.state
' "s.mote:2:" "error:"

expect_invalid "step before any system" 'step 10
new 2 0.4
' "s.mote:1:1: error:" "no system"

expect_invalid "eta above eta_max" 'new 2 0.7
' "s.mote:1:" "error:" "eta_max" "0.606146"

expect_invalid "bulk with N not 4n^3" 'bulk 100 0.3
' "s.mote:1:" "error:" "32" "108"

expect_invalid "compress in a periodic box" 'bulk 32 0.3
save early.state
compressl 0.35 0.1 1
' "s.mote:3:1: error:" "periodic"

expect_invalid "output into a missing directory" 'new 2 0.4
save early.state
save nodir/late.state
' "s.mote:3:6: error:" "nodir/late.state" "does not exist"

expect_invalid "negative K" 'new 2 0.4
step -5
' "s.mote:2:6: error:"

expect_invalid "upper-case command" 'NEW 2 0.4
' "s.mote:1:1: error:" "unknown command" "lower-case"

expect_invalid "error on the last line of a long script" 'new 2 0.4
step 1
save a.state
image 1 10 img.txt
step 1
save b.state
stepp 1
' "s.mote:7:1: error:" "did you mean 'step'"

# `mote check` on a bad script also exits with 1
new_case
printf 'new 2 0.4\nsave x.state\nstep 1e3\n' >"$D/s.mote"
run_mote check s.mote
if [ "$rc" -eq 1 ] && [ -z "$(files_in_case)" ]; then ok "mote check on a bad script: exit 1, nothing written"; else not_ok "mote check on a bad script" "rc $rc, files: $(files_in_case)"; fi

# a missing script
new_case
run_mote run missing.mote
if [ "$rc" -eq 1 ] && grep -q "missing.mote" "$ERR"; then ok "missing script: exit 1, named"; else not_ok "missing script: exit 1, named" "rc $rc: $(cat "$ERR")"; fi

# writing the same file twice is a warning, not an error
new_case
printf 'new 2 0.4\nsave a.state\nstep 1\nsave a.state\n' >"$D/s.mote"
run_mote run s.mote
if [ "$rc" -eq 0 ] && grep -q "s.mote:4:.*warning" "$ERR" && [ -s "$D/a.state" ]; then ok "the same output twice: a located warning"; else not_ok "the same output twice: a located warning" "rc $rc: $(cat "$ERR")"; fi

# ---- runtime error: exit 2, earlier files intact ---------------------------------------------------

new_case
printf 'new 2 0.4\nstep 1\nsave full.state\n' >"$D/s.mote"
run_mote run s.mote
if [ "$rc" -eq 0 ] && [ -f "$D/full.state" ]; then ok "make a state file"; else not_ok "make a state file" "rc $rc: $(cat "$ERR")"; fi
head -n 30 "$D/full.state" >"$T/trunc.state"
cp "$D/full.state" "$T/full.state"

new_case
cp "$T/trunc.state" "$D/trunc.state"
printf 'new 2 0.4\nsave a.state\nload trunc.state\nsave b.state\n' >"$D/s.mote"
run_mote run s.mote
if [ "$rc" -eq 2 ]; then ok "runtime error (truncated state): exit status 2"; else not_ok "runtime error (truncated state): exit status 2" "rc $rc: $(cat "$ERR")"; fi
if grep -q -F "s.mote:3:1: error:" "$ERR" && grep -q -F "trunc.state:31:" "$ERR" && grep -q "ends early" "$ERR"; then
    ok "runtime error: located at the command, names the file's line"
else
    not_ok "runtime error: located at the command, names the file's line" "$(cat "$ERR")"
fi
if [ -f "$D/a.state" ] && [ "$(tail -n 1 "$D/a.state")" = "end" ] && [ "$(wc -l <"$D/a.state")" -eq 76 ]; then
    ok "runtime error: the earlier save is complete"
else
    not_ok "runtime error: the earlier save is complete" "$(ls -l "$D")"
fi
extra=$(files_in_case -e trunc.state -e a.state)
if [ -z "$extra" ]; then ok "runtime error: no later or temporary file"; else not_ok "runtime error: no later or temporary file" "found: $extra"; fi
if [ "$(grep -c "^N=" "$OUT")" -eq 2 ]; then ok "runtime error: the two commands before it ran"; else not_ok "runtime error: the two commands before it ran" "$(cat "$OUT")"; fi

# ---- the original document's examples --------------------------------------------------------------

new_case
cat >"$D/s.mote" <<'EOF'
new 8 0.4
save save_file_0.40000_10000.txt
load save_file_0.40000_10000.txt
step 1000
step 10000
compress_left_wall 0.503423 0.000001 10
compressr 0.49 0.0000001 1000
compress_right_wall 0.49 0.0000001 1000
EOF
run_mote check s.mote
if [ "$rc" -eq 0 ] && grep -q "ok" "$OUT" && [ -z "$(files_in_case)" ]; then
    ok "the original document's examples pass validation (mote check), nothing written"
else
    not_ok "the original document's examples pass validation" "rc $rc: $(cat "$ERR") $(cat "$OUT")"
fi

# a scaled-down equivalent that runs, with blank lines, comments, quotes and CRLF line ends
new_case
printf '%s\r\n' \
    '# scaled-down version of the original example' \
    '' \
    'new 2 0.4        # 64 spheres' \
    '   ' \
    'step 2' \
    'save "save file 0.40000.txt"' \
    'load "save file 0.40000.txt"' \
    'step 1' \
    'compress_left_wall 0.42 0.05 1' \
    'compressr 0.41 0.05 1' \
    'compresst 0.40 0.05 1' \
    'image 2 10 image.txt' \
    'profile 3 6 2 2 cut.txt' \
    'check' \
    'save final.state' >"$D/s.mote"
run_mote run s.mote
if [ "$rc" -eq 0 ]; then ok "scaled-down example runs"; else not_ok "scaled-down example runs" "rc $rc: $(cat "$ERR")"; fi
for f in "save file 0.40000.txt" image.txt cut.txt final.state; do
    if [ -s "$D/$f" ]; then ok "scaled-down example wrote '$f'"; else not_ok "scaled-down example wrote '$f'"; fi
done
if grep -q "^# columns:" "$D/image.txt" && grep -q "^# command: image 2 10 image.txt" "$D/image.txt"; then
    ok "image file header names its columns and command"
else
    not_ok "image file header names its columns and command" "$(head -n 5 "$D/image.txt")"
fi
last=$(grep "^N=" "$OUT" | tail -n 1)
missing=""
for key in "N=64" "eta=0.4 " "A=" "L=" "t=" "collisions=" "E="; do
    case "$last" in
    *"$key"*) ;;
    *) missing="$missing [$key]" ;;
    esac
done
if [ -z "$missing" ]; then ok "status line has N=, eta=, A=, L=, t=, collisions=, E="; else not_ok "status line keys" "lacks$missing: $last"; fi
if [ "$(grep -c "^N=" "$OUT")" -eq 12 ]; then ok "one status line per model command"; else not_ok "one status line per model command" "$(grep -c "^N=" "$OUT") lines"; fi
if grep -q "check: all invariants hold" "$OUT"; then ok "check command reports success"; else not_ok "check command reports success" "$(cat "$OUT")"; fi
cp "$D/final.state" "$T/final1.state"
cp "$D/image.txt" "$T/image1.txt"
cp "$D/s.mote" "$T/example.mote"

# determinism: the same script again gives byte-identical files
new_case
cp "$T/example.mote" "$D/s.mote"
run_mote run s.mote
if cmp -s "$D/final.state" "$T/final1.state" && cmp -s "$D/image.txt" "$T/image1.txt"; then
    ok "the same script twice: byte-identical files"
else
    not_ok "the same script twice: byte-identical files"
fi

# a measurement advances the system exactly as step does
new_case
printf 'new 3 0.45\nimage 5 10 i.txt\nprofile 2 5 3 4 p.txt\nsave a.state\n' >"$D/s.mote"
run_mote run s.mote
mv "$D/a.state" "$T/measured.state"
printf 'new 3 0.45\nstep 5\nstep 4\nsave a.state\n' >"$D/s.mote"
run_mote run s.mote
if cmp -s "$D/a.state" "$T/measured.state"; then ok "image 5 + profile ... 4 end where step 5 + step 4 end"; else not_ok "image/profile perturb the trajectory"; fi

# load, then continue == uninterrupted (through the program)
new_case
printf 'new 2 0.45\nstep 10\nsave mid.state\nstep 20\nsave end.state\n' >"$D/s.mote"
run_mote run s.mote
mv "$D/end.state" "$T/end1.state"
printf 'load mid.state\nstep 20\nsave end.state\n' >"$D/s.mote"
run_mote run s.mote
if [ "$rc" -eq 0 ] && cmp -s "$D/end.state" "$T/end1.state"; then ok "continued from a saved state: byte-identical"; else not_ok "continued from a saved state" "rc $rc: $(cat "$ERR")"; fi

# an original-program state file loads through the script (validation peeks its header)
new_case
cat >"$D/orig.txt" <<'EOF'
4
0
5.000000000000000
8.000000000000000
0 0
2.000000000000000 1.000000000000000 1.000000000000000
0.5000000000000000 0.1000000000000000 -0.2000000000000000
1 1
2.000000000000000 3.500000000000000 3.500000000000000
-0.3000000000000000 0.2000000000000000 0.1000000000000000
2 2
5.000000000000000 1.000000000000000 3.500000000000000
0.1000000000000000 -0.4000000000000000 0.3000000000000000
3 3
5.000000000000000 3.500000000000000 1.000000000000000
-0.2000000000000000 0.3000000000000000 0.2000000000000000
EOF
printf 'load orig.txt\ntemperature 1\nstep 20\ncheck\n' >"$D/s.mote"
run_mote run s.mote
if [ "$rc" -eq 0 ] && grep -q "kT=1$" "$OUT"; then ok "original-format file loads and runs"; else not_ok "original-format file loads and runs" "rc $rc: $(cat "$ERR") $(cat "$OUT")"; fi

# `mote run` without a script runs program.txt
new_case
printf 'new 2 0.4\nstep 1\n' >"$D/program.txt"
run_mote run
if [ "$rc" -eq 0 ] && grep -q "N=64" "$OUT"; then ok "mote run without a script runs program.txt"; else not_ok "mote run runs program.txt" "rc $rc: $(cat "$ERR")"; fi

# ---- help and version --------------------------------------------------------------------------------

new_case
run_mote --version
if [ "$rc" -eq 0 ] && grep -q "^mote [0-9][0-9.]*" "$OUT"; then ok "mote --version"; else not_ok "mote --version" "rc $rc: $(cat "$OUT")"; fi
run_mote help
if [ "$rc" -eq 0 ] && grep -q "compress_left_wall" "$OUT" && grep -q "step" "$OUT" && grep -q "image" "$OUT"; then ok "mote help lists the commands"; else not_ok "mote help" "rc $rc"; fi
run_mote help step
if [ "$rc" -eq 0 ] && grep -q "step K" "$OUT"; then ok "mote help step"; else not_ok "mote help step" "rc $rc: $(cat "$OUT")"; fi
run_mote help compressl
if [ "$rc" -eq 0 ] && grep -q "compress_left_wall eta dLmax K" "$OUT"; then ok "mote help compressl (alias) documents compress_left_wall"; else not_ok "mote help compressl" "rc $rc: $(cat "$OUT")"; fi
run_mote help nosuch
if [ "$rc" -eq 1 ] && grep -q "nosuch" "$ERR"; then ok "mote help nosuch: exit 1"; else not_ok "mote help nosuch: exit 1" "rc $rc"; fi
run_mote
if [ "$rc" -eq 1 ]; then ok "mote without arguments: exit 1"; else not_ok "mote without arguments: exit 1" "rc $rc"; fi

# quiet (issue 52): no status line after each command with `quiet on` or --quiet; the results
# and the command's own lines still print
printf 'new 2 0.3\nquiet on\nstep 10\npressure 10 q.dat\nquiet off\nstep 10\n' > "$T/q.mote"
n=$("$MOTE" run "$T/q.mote" 2>&1 | grep -c '^N=')
if [ "$n" -eq 2 ]; then ok "quiet on/off: status lines after new and the last step only"; else not_ok "quiet on/off" "$n status lines"; fi
out=$("$MOTE" run --quiet "$T/q.mote" 2>&1)
n=$(printf '%s\n' "$out" | grep -c '^N=')
if [ "$n" -eq 1 ] && printf '%s\n' "$out" | grep -q '^pressure: '; then ok "--quiet: one status line (after quiet off), results still printed"; else not_ok "--quiet" "$out"; fi

# the threads help lists the models from the registry (which use threads, which run on one)
th=$("$MOTE" help threads 2>&1)
if printf '%s\n' "$th" | grep -q '^Models that use threads: nbody, charging, separator\.$' &&
    printf '%s\n' "$th" | grep -q '^Models on one thread: hard-spheres, mixing-box\.$'; then
    ok "help threads: the models listed from the registry"
else not_ok "help threads" "$th"; fi

# Ctrl-C: the running command stops at a safe point and mote exits 128 + the signal, saying so
# (SIGTERM as SIGINT); a command that does not stop within 3 s (one N-body step has no safe point
# inside it) ends at once, as the signal would end it without mote. A background job ignores
# SIGINT unless told otherwise (env --default-signal).
# signalled NAME WORD SIG: run $T/NAME.mote in the background, send SIG once it has printed WORD;
# its exit status in rc, its output in $T/NAME.out and .err
signalled() {
    # (the last run's output gone first: its WORD must not be taken for this run's, which may not
    # have opened the file yet, and a signal before mote has started ends it as it would any
    # program)
    rm -f "$T/$1.out" "$T/$1.err"
    env --default-signal=INT "$MOTE" run "$T/$1.mote" > "$T/$1.out" 2> "$T/$1.err" &
    pid=$!
    i=0
    while ! grep -q "$2" "$T/$1.out" 2>/dev/null && [ $i -lt 1200 ]; do sleep 0.1; i=$((i + 1)); done
    kill -"$3" $pid
    wait $pid
    rc=$?
}
printf 'bulk 500 0.3\necho stepping\nstep 100000\n' > "$T/long.mote"
for sig in INT TERM; do
    signalled long stepping $sig
    want=$([ $sig = INT ] && echo "130 Ctrl-C (SIGINT)" || echo "143 Terminated")
    if [ "$rc" -eq "${want%% *}" ] && grep -q "long.mote:3:1: error: step: interrupted; it stopped at a safe point" "$T/long.err" &&
        grep -q "^mote: stopped by ${want#* }$" "$T/long.err"; then
        ok "SIG$sig stops the run at a safe point, exit $rc"
    else not_ok "SIG$sig" "exit $rc: $(cat "$T/long.err")"; fi
done
# the boundary-element solve of a body's field (5 120 panels, seconds) hears Ctrl-C between its
# blocks of rows and of the LU: a safe-point stop, nothing solved
printf 'model charging\nbody icosphere radius=1 level=4\necho solving\nbody capacitance value=solve\n' > "$T/bem.mote"
signalled bem solving INT
if [ "$rc" -eq 130 ] && grep -q "bem.mote:4:24: error: body capacitance: solve: interrupted; it stopped at a safe point" "$T/bem.err" &&
    grep -q "^mote: stopped by Ctrl-C (SIGINT)$" "$T/bem.err" && ! grep -q "solved" "$T/bem.out"; then
    ok "SIGINT stops the boundary-element solve at a safe point, exit 130"
else not_ok "SIGINT in the boundary-element solve" "exit $rc: $(cat "$T/bem.err" "$T/bem.out")"; fi
# one N-body step of 10^5 bodies (direct sums, tens of seconds) has no safe point inside it
printf 'model nbody\ngenerate plummer n=100000\necho stepping\nintegrate steps=1\n' > "$T/hard.mote"
signalled hard stepping INT
if [ "$rc" -eq 130 ] && ! grep -q "stopped\|interrupted\|steps=1 " "$T/hard.err" "$T/hard.out"; then
    ok "a command that does not stop within 3 s ends as the signal would end it"
else not_ok "a command that does not stop" "exit $rc: $(cat "$T/hard.err" "$T/hard.out")"; fi

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ] && [ "$passed" -gt 0 ]
