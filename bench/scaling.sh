#!/bin/sh
# scaling.sh: each threaded model's benchmark at 1, 2, 4, ... threads up to the processors of the
# machine (and nproc itself), and the efficiency table: rate(T) / (T rate(1)). With MPI_BUILD set
# to an MPI build's directory (make MPI=1 BUILD=build-mpi bench), also 1, 2, 4, ... ranks under
# mpirun for the models that share their work between ranks (charging, nbody).
# Usage: sh bench/scaling.sh [BUILD_DIR] [QUICK]   (default: build; QUICK=1: smaller workloads)
#   make BUILD=build-o3 OPT=-O3 bench && sh bench/scaling.sh build-o3
# Timings only mean something on a machine with nothing else running; see bench/README.md.
B=$(cd "${1:-build}" && pwd) || exit 1
Q=${2:-0}
P=$(nproc)
for x in bench_separator bench_charging bench_nbody; do
    [ -x "$B/bench/$x" ] || { echo "scaling.sh: $B/bench/$x is missing (make BUILD=... bench)" >&2; exit 1; }
done
if [ "$Q" = 1 ]; then
    SEP3="ref3d 100000 10"; COL="column 20000 500"; CH=3e6; NB=4000
else
    SEP3="ref3d 1000000 5"; COL="column 20000 2000"; CH=2e7; NB=20000
fi
# the thread counts: 1, 2, 4, ... below nproc, then nproc
counts() {
    t=1
    while [ "$t" -lt "$1" ]; do printf '%s ' "$t"; t=$((t * 2)); done
    printf '%s\n' "$1"
}
# key=value out of a line
val() { sed -n "s/.*[ ^]$1=\([0-9.e+-]*\).*/\1/p" | head -n 1; }

printf '%-28s %8s %14s %10s\n' "workload" "threads" "rate" "efficiency"
row() { # name threads rate base
    awk -v n="$1" -v t="$2" -v r="$3" -v b="$4" \
        'BEGIN { printf "%-28s %8d %14.4g %9.1f%%\n", n, t, r, (b > 0 ? 100 * r / (t * b) : 0) }'
}
run_model() { # name key command...
    name=$1; key=$2; shift 2
    base=
    for t in $(counts "$P"); do
        r=$("$@" "$t" | val "$key")
        [ -z "$r" ] && { echo "scaling.sh: $name on $t threads printed no $key" >&2; continue; }
        [ -z "$base" ] && base=$r
        row "$name" "$t" "$r" "$base"
    done
}
# shellcheck disable=SC2086
run_model "separator $SEP3 (steps/s)" steps_per_s "$B/bench/bench_separator" $SEP3
# shellcheck disable=SC2086
run_model "separator $COL (steps/s)" steps_per_s "$B/bench/bench_separator" $COL
run_model "charging b1 $CH (traces/s)" traces_per_s "$B/bench/bench_charging" b1 "$CH"
run_model "nbody pairs $NB (pairs/s)" pair_evaluations_per_second "$B/bench/bench_nbody" pairs "$NB"
if [ -n "${MPI_BUILD:-}" ]; then
    M=$(cd "$MPI_BUILD" && pwd) || exit 1
    printf '%-28s %8s %14s %10s\n' "workload (MPI, 1 thread)" "ranks" "rate" "efficiency"
    for pair in "charging:bench_charging b1 $CH 1:traces_per_s" "nbody:bench_nbody pairs $NB 1:pair_evaluations_per_second"; do
        name=${pair%%:*}; rest=${pair#*:}; cmd=${rest%:*}; key=${rest##*:}
        base=
        for n in $(counts "$P"); do
            # shellcheck disable=SC2086
            r=$(OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \
                mpirun --oversubscribe -np "$n" "$M/bench/"$cmd 2>/dev/null | val "$key")
            [ -z "$r" ] && continue
            [ -z "$base" ] && base=$r
            row "$name ranks" "$n" "$r" "$base"
        done
    done
fi
