#!/bin/sh
# seeds.sh BUILD_DIR [K] [FIRST]: run every test program again with MOTE_TEST_SEED = FIRST .. K
# (default 1 .. 20), that is with other realisations of every random start (see test_seed in
# tests/test.h), two at a time, and list each failing check with its seed. A statistical tolerance of 3 standard
# errors fails in about 0.3% of realisations per check, so across K seeds a check that fails
# more than once or twice is too tight or its run too short. Each program gets at most 600 s (a
# slow seed is reported as exit 124). Not part of `make check` (about 20 s per seed on two
# cores); `make seeds` runs it.
set -u
build=${1:-build}
K=${2:-20}
FIRST=${3:-1}
here=$(cd "$(dirname "$0")" && pwd)
cd "$here/.." || exit 1
out=$(mktemp -d)
for k in $(seq "$FIRST" "$K"); do
    for t in "$build"/tests/test_*; do
        [ -x "$t" ] && echo "$k $t"
    done
done | xargs -P 2 -L 1 sh -c 'log="'"$out"'/$(basename "$1").$0.log"
    MOTE_TEST_SEED=$0 timeout 600 "$1" > "$log" 2>&1 || echo "EXITED $(basename "$1") with status $?" >> "$log"'
fails=0
for f in "$out"/*.log; do
    base=$(basename "$f" .log)
    if grep -q "FAILED\|^EXITED" "$f"; then
        grep "FAILED\|^EXITED" "$f" | sed "s|^|seed ${base##*.}: |"
        fails=$((fails + 1))
    fi
done
rm -rf "$out"
echo "seeds $FIRST..$K: $fails program runs failed a check or exited with an error"
[ "$fails" -eq 0 ]
