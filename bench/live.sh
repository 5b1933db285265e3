#!/bin/sh
# live.sh: what the live view costs a run (issue 25): a mixing box of 10^4 disks run for 20 s of
# simulated time, alternately without a viewer and with one reading the frame stream at 30 Hz
# (curl), ROUNDS times each; prints each run's wall seconds and the median slowdown.
# Usage: sh bench/live.sh [BUILD_DIR] [ROUNDS]   (default: build, 3)
B=$(cd "${1:-build}" && pwd)
R=${2:-3}
T=$(mktemp -d) || exit 1
trap 'rm -rf "$T"' EXIT
cd "$T" || exit 1
printf 'model mixing-box\nseed 7\nbox 0 4 0 2\npartition 2 0.02\nslit 1 0.2\nradius 0.005\ndisks 5000 5000\nv_init 1\nplace\nrun 20\n' > big.mote
: > times.txt
i=0
while [ "$i" -lt "$R" ]; do
    p=$("$B/mote" run big.mote | sed -n 's/.* wall_seconds=\([0-9.]*\).*/\1/p')
    "$B/mote" run --live=0 big.mote > live.txt 2>&1 &
    pid=$!
    url=
    while [ -z "$url" ]; do url=$(sed -n 's/^live: open \(http[^ ]*\) .*/\1/p' live.txt); sleep 0.05; done
    curl -s -N "${url}stream" | grep -c '^data: ' > frames.txt &
    wait "$pid"
    sleep 0.2
    l=$(sed -n 's/.* wall_seconds=\([0-9.]*\).*/\1/p' live.txt)
    echo "workload=live_cost N=10000 plain_seconds=$p live_seconds=$l frames=$(cat frames.txt)"
    echo "$p $l" >> times.txt
    i=$((i + 1))
done
sort -n -k1 times.txt > /dev/null
awk '{ r[NR] = $2 / $1 } END { n = asort(r); printf "median_slowdown=%.1f%%\n", 100 * (r[int((n + 1) / 2)] - 1) }' times.txt 2> /dev/null ||
    awk '{ s += $2 / $1 } END { printf "mean_slowdown=%.1f%%\n", 100 * (s / NR - 1) }' times.txt
