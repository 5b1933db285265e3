#!/bin/sh
# threads.sh: does a second thread ever make a run slower? Each model that runs on threads runs
# one short script through the program users get (build/mote), on 1 and 2 threads, first on a
# quiet machine, then beside two busy processes (shell loops that never sleep), and prints the
# wall times and 1-thread time / 2-thread time (above 1: the second thread helped). On a busy
# 2-core machine libgomp's default spinning made the separator's 2 threads 25x slower than one;
# mote's programs set a spin count of 1000 (mote_threads_quiet, include/mote/core.h).
#
# Usage: sh bench/threads.sh [BUILD_DIR] [SCALE]   (default: build, 1; SCALE multiplies the work)
#   GOMP_SPINCOUNT=300000 sh bench/threads.sh   the libgomp default, for comparison
# Not a timed test: bench/README.md keeps the figures.
B=$(cd "${1:-build}" && pwd) || exit 1
S=${2:-1}
[ -x "$B/mote" ] || { echo "threads.sh: $B/mote is missing (make BUILD=...)" >&2; exit 1; }
W=$(mktemp -d) || exit 1
busy=
cleanup() {
    for p in $busy; do kill "$p" 2>/dev/null; done
    rm -rf "$W"
}
trap cleanup EXIT INT TERM

# the workloads: one script each, ${T} its thread count
cat > "$W/separator.mote" <<EOF
model separator
threads \${T}
dim 3
channel 0.04 0.2 D=0.04
ends closed closed
gas 0
species sand density=2500
size sand lognormal d50=1.5e-3 sigma=1.2 min=1e-3 max=2e-3
feed z=0.1 hf=0.18 rate=0
insert sand 20000
restitution 0.5
run $(awk -v s="$S" 'BEGIN { print 0.0006 * s }')
EOF
cat > "$W/charging.mote" <<EOF
model charging faithful
threads \${T}
body sphere radius=1
run particles=$(awk -v s="$S" 'BEGIN { print 3e7 * s }')
EOF
cat > "$W/nbody.mote" <<EOF
model nbody
threads \${T}
generate plummer n=1000 seed=3
integrator taylor order=12 tol=1e-12
integrate for=$(awk -v s="$S" 'BEGIN { print 0.02 * s }')
EOF
cat > "$W/hard-spheres.mote" <<EOF
model hard-spheres
threads \${T}
ensemble 2
new 4 0.35
step $(awk -v s="$S" 'BEGIN { print 2000 * s }')
pressure 10 p.dat
end
EOF

wall() { # script threads: the wall seconds of one run
    s=$(date +%s.%N)
    MOTE_PROGRESS=0 "$B/mote" run "$W/$1.mote" T="$2" > "$W/out" 2>&1 ||
        { echo "threads.sh: $1 on $2 threads failed:" >&2; tail -n 5 "$W/out" >&2; }
    e=$(date +%s.%N)
    awk -v s="$s" -v e="$e" 'BEGIN { printf "%.2f", e - s }'
}
table() { # label
    for m in separator charging nbody hard-spheres; do
        t1=$(wall "$m" 1)
        t2=$(wall "$m" 2)
        awk -v l="$1" -v m="$m" -v a="$t1" -v b="$t2" \
            'BEGIN { printf "%-10s %-13s %9.2f %9.2f %8.2f\n", l, m, a, b, (b > 0 ? a / b : 0) }'
    done
}
printf '# %s, %s processors, GOMP_SPINCOUNT=%s OMP_WAIT_POLICY=%s\n' \
    "$(sed -n 's/^model name[^:]*: //p' /proc/cpuinfo | head -n 1)" "$(nproc)" \
    "${GOMP_SPINCOUNT:-(mote: 1000)}" "${OMP_WAIT_POLICY:-unset}"
printf '%-10s %-13s %9s %9s %8s\n' "machine" "model" "1 thread" "2 threads" "t1/t2"
table quiet
sh -c 'while :; do :; done' & busy="$busy $!"
sh -c 'while :; do :; done' & busy="$busy $!"
table busy
