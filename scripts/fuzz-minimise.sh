#!/bin/sh
# fuzz-minimise.sh BUILD_DIR [TARGET ...]: shrink each target's corpus in fuzz/corpus/<target>/
# to the fewest of its fuzzer units (files named by their SHA-1) that reach the same coverage
# (libFuzzer's -merge=1), keeping every named file (seeds, crashers, hangs) as it is. Run by
# `make fuzz-minimise` after `make fuzz` (which builds BUILD_DIR/fuzz_<target>); `make check`
# replays the corpus, so a smaller one is a faster suite that checks the same paths.
set -eu
B=$1
shift
targets=${*:-$(ls fuzz/corpus)}
before=0
after=0
for t in $targets; do
    bin=$B/fuzz_$t
    dir=fuzz/corpus/$t
    [ -x "$bin" ] || { echo "fuzz-minimise: $bin is missing (make fuzz)" >&2; exit 1; }
    [ -d "$dir" ] || { echo "fuzz-minimise: no corpus $dir" >&2; exit 1; }
    work=$(mktemp -d)
    mkdir "$work/units"
    n0=$(ls "$dir" | wc -l)
    # the units are merged into the folder that holds the named files alone: those count as
    # covered already, and a unit is kept only when it reaches something more
    for f in "$dir"/*; do
        name=$(basename "$f")
        if echo "$name" | grep -qE '^[0-9a-f]{40}$'; then
            mv "$f" "$work/units/"
        fi
    done
    if [ -n "$(ls "$work/units")" ]; then
        ASAN_OPTIONS=detect_leaks=0 "$bin" -merge=1 -use_counters=0 -timeout=30 -rss_limit_mb=2048 \
            -max_len=4096 "$dir" "$work/units" > "$work/log" 2>&1 ||
            { cat "$work/log" >&2; mv "$work/units"/* "$dir/"; rm -rf "$work"; exit 1; }
    fi
    n1=$(ls "$dir" | wc -l)
    echo "fuzz-minimise: $t: $n0 -> $n1 files"
    before=$((before + n0))
    after=$((after + n1))
    rm -rf "$work"
done
echo "fuzz-minimise: $before -> $after files in all"
