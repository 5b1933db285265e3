#!/bin/sh
# test_readers.sh: every reader of every model on /dev/zero and on a 2 GB sparse file (zeros,
# no newline), under a 1 GB address-space limit (issue 33): each must end with a clean error
# (exit 1 or 2, a message naming the file), within a minute, never killed by a signal and never
# growing past the limit. Under the sanitizers (MOTE_SANITIZED) the address-space limit is left
# out (AddressSanitizer reserves terabytes of shadow memory), /dev/zero alone is read, and the
# mesh reader's sparse file is 128 MB.
# Usage: sh tests/test_readers.sh [BUILD_DIR]
NAME=readers
. "$(dirname "$0")/lib.sh"
SRC=$(cd "$(dirname "$0")/.." && pwd)
mote_test_start "$1"

truncate -s 2G sparse.dat 2> /dev/null || dd if=/dev/zero of=sparse.dat bs=1 count=0 seek=2G 2> /dev/null
inputs="/dev/zero"
[ -z "${MOTE_SANITIZED:-}" ] && [ -f sparse.dat ] && inputs="$inputs $PWD/sparse.dat"
limit() { # run the rest under the address-space limit (not with the sanitizers)
    if [ -n "${MOTE_SANITIZED:-}" ]; then
        timeout 60 "$@"
    else
        (ulimit -v 1048576 && exec timeout 60 "$@")
    fi
}
# one KIND SCRIPT-TEXT: run the script (F stands for the input) on each input
one() {
    kind=$1
    for f in $inputs; do
        printf '%b' "$(printf '%s' "$2" | sed "s|F|$f|g")" > r.mote
        limit "$MOTE" run r.mote > out.txt 2> err.txt
        rc=$?
        if [ "$rc" -ge 1 ] && [ "$rc" -le 2 ] &&
            grep -q "error: .*$(basename "$f").*\(line longer than 1 MiB\|not a regular file\|not a mesh file Assimp reads\|Assimp could not\)" err.txt; then
            ok
        else
            bad "$kind on $f: exit $rc, $(head -c 300 err.txt)"
        fi
    done
}
for f in $inputs; do # the script itself
    limit "$MOTE" check "$f" > out.txt 2> err.txt
    rc=$?
    [ "$rc" -eq 1 ] && grep -q "$(basename "$f"): a script larger than 64 MiB" err.txt && ok || bad "script $f: exit $rc, $(head -c 300 err.txt)"
done
one "hard spheres load" 'load F\n'
one "mixing box load" 'model mixing-box\nload F\n'
one "nbody load" 'model nbody\nload F\n'
one "nbody restart" 'model nbody\nrestart file=F\n'
one "nbody read snapshot" 'model nbody\nread snapshot file=F\n'
one "nbody read galactica" 'model nbody\nread galactica file=F\n'
one "nbody solar system data" 'model nbody\ngenerate solar_system data=F\n'
one "separator load" 'model separator\nload F\n'
one "separator gas_profile" 'model separator\nchannel 0.05 1\ngas_profile F\n'
one "separator size table" 'model separator\nchannel 0.05 1\nspecies a 2500\nsize a table file=F\n'
one "separator grid holes" 'model separator\nchannel 0.05 1\ngrid 0.3 0.01 holes file=F\n'
one "separator classes_file" 'model separator\nclasses_file F\n'
one "plot" 'new 8 0.3\nplot F p.png\n'
one "charging plain mesh" 'model charging\nbody load file=F format=plain\n'
one "charging mesh (Assimp)" 'model charging\nbody load file=F format=assimp\n'
# the sparse file under each extension Assimp knows (under the sanitizers a 128 MB one: the same
# paths of the reader, without reading 2 GB four times at the sanitizers' pace)
zeros=sparse.dat
[ -n "${MOTE_SANITIZED:-}" ] && truncate -s 128M zeros.dat 2> /dev/null && zeros=zeros.dat
for ext in stl off ply obj; do
    ln -s "$zeros" "zero.$ext"
    printf 'model charging\nbody load file=zero.%s\n' "$ext" > r.mote
    limit "$MOTE" run r.mote > out.txt 2> err.txt
    rc=$?
    [ "$rc" -eq 2 ] && grep -q "error: body load: zero.$ext: " err.txt && ok || bad "zero.$ext: exit $rc, $(head -c 300 err.txt)"
done
# the long-line message itself, for the core reader
printf 'model nbody\nload /dev/zero\n' > z.mote
"$MOTE" run z.mote > out.txt 2> err.txt
grep -q '^z.mote:2:6: error: load: /dev/zero:1: line longer than 1 MiB (not a text file?)$' err.txt && ok || bad "the line limit's message: $(cat err.txt)"
# Galactica: a control file, and the body file of a continuation (Kl1 = 1)
for f in $inputs; do
    rm -rf job && mkdir job
    (cd job && limit "$MOTE" galactica --control "$f" > ../out.txt 2> ../err.txt)
    rc=$?
    [ "$rc" -ge 1 ] && [ "$rc" -le 2 ] && grep -q "$(basename "$f").*line longer than 1 MiB" err.txt && ok || bad "galactica --control $f: exit $rc, $(head -c 300 err.txt)"
    rm -rf job && cp -r "$SRC/examples/galactica/ring30" job
    sed -i 's/^\(Key: input data from file *\)2/\11/' job/galacf26.dat
    ln -s "$f" job/garez28.dat
    (cd job && limit "$MOTE" galactica > ../out.txt 2> ../err.txt)
    rc=$?
    [ "$rc" -ge 1 ] && [ "$rc" -le 2 ] && grep -q "garez28.dat.*line longer than 1 MiB" err.txt && ok || bad "galactica garez28.dat on $f: exit $rc, $(head -c 300 err.txt)"
done
mote_test_end
