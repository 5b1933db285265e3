#!/bin/sh
# test_bench.sh BUILD_DIR: the benchmark runner's workloads on tiny systems (no timing is
# checked): the slit's periodic twin has the slit's N and eta, no walls and no overlap; an
# interleaved pair reports its ratio; a twin too dense to build and an unknown workload fail
# with a message.
build=$(cd "${1:-build}" && pwd)
bench="$build/bench/bench_hs"
pass=0
fail=0
ok() { pass=$((pass + 1)); echo "ok: $1"; }
bad() { fail=$((fail + 1)); echo "FAIL: $1"; }
check() { if eval "$2"; then ok "$1"; else bad "$1"; fi; }
val() { echo "$1" | grep -o " $2=[^ ]*" | head -n 1 | cut -d= -f2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

[ -x "$bench" ] || { echo "FAIL: no $bench"; echo "0 passed, 1 failed"; exit 1; }
out=$("$bench" 2 slit3:0.45 twin3:0.45 2>"$tmp/err")
check "slit3 and twin3 run" '[ $? -eq 0 ] && [ ! -s "$tmp/err" ]'
slit=$(echo "$out" | grep '^workload=slit3')
twin=$(echo "$out" | grep '^workload=twin3')
check "the twin has the slit's N ($(val "$slit" N))" '[ -n "$slit" ] && [ "$(val "$twin" N)" = "$(val "$slit" N)" ]'
check "the twin has the slit's eta ($(val "$twin" eta))" '[ "$(val "$twin" eta)" = 0.45 ] && [ "$(val "$slit" eta)" = 0.45 ]'
check "the twin is periodic and has no wall hits" \
    '[ "$(val "$twin" geometry)" = periodic ] && [ "$(val "$twin" wall_hits_per_collision)" = 0.0000 ]'
check "the slit hits its walls" '[ "$(val "$slit" geometry)" = slit ] && [ "$(val "$slit" wall_hits_per_collision)" != 0.0000 ]'
check "both count 2 collisions per particle" \
    '[ "$(val "$twin" collisions)" = $(( $(val "$twin" N) )) ] && [ "$(val "$slit" collisions)" = $(( $(val "$slit" N) )) ]'

pair=$("$bench" 4 slit5:0.45/twin5:0.45 2>"$tmp/err" | grep "^pair=")
check "an interleaved pair reports its rate ratio" \
    'echo "$pair" | grep -q "^pair=slit5:0.45/twin5:0.45 chunks=20 rate_ratio=[0-9]"'

"$bench" 2 twin2:0.55 >/dev/null 2>"$tmp/err"
rc=$?
check "a twin too close to eta_max fails (exit $rc): $(head -c 80 "$tmp/err")" \
    '[ $rc -ne 0 ] && grep -q "twin2:0.55: .*overlapping" "$tmp/err"'
"$bench" 2 cube3:0.45 >/dev/null 2>"$tmp/err"
rc=$?
check "an unknown workload fails (exit $rc)" '[ $rc -ne 0 ] && grep -q "unknown workload .cube3:0.45." "$tmp/err"'

# the N-body benchmark: its workloads run and report (no timing is checked)
nbench="$(dirname "$bench")/bench_nbody"
b1=$("$nbench" b1 12 1e-12 2>"$tmp/err")
check "bench_nbody b1 reports steps, CPU time and the ring error: $(head -c 80 "$tmp/err")" \
    'echo "$b1" | grep -q "^workload=b1 precision=double integrator=taylor order=12 tol=1e-12 steps=[0-9]* cpu_seconds_median=[0-9.]* cpu_seconds_min=[0-9.]* error=[0-9.e+-]* abs_dE="'
b2=$("$nbench" b2 data/outer_solar_system.dat 10 1e-10 2>"$tmp/err")
check "bench_nbody b2 reports steps, CPU time and the energy and moment errors: $(head -c 80 "$tmp/err")" \
    'echo "$b2" | grep -q "^workload=b2 precision=double integrator=taylor order=10 tol=1e-10 rotation=0 steps=[0-9]* cpu_seconds_median=[0-9.]* cpu_seconds_min=[0-9.]* max_abs_dE=[0-9.e+-]* abs_dE_end=[0-9.e+-]* abs_dL_end="'
pairs=$("$nbench" pairs 100 2 2>"$tmp/err")
check "bench_nbody pairs reports pair evaluations per second" \
    'echo "$pairs" | grep -q "^workload=pairs precision=double N=100 threads=2 steps=3 wall_seconds=[0-9.]* pair_evaluations_per_second="'
cl=$("$nbench" cluster 20 0.05 10 1e-12 3 "$tmp/ic.txt" 2>"$tmp/err")
check "bench_nbody cluster reports steps, CPU time and |dE| and writes the 20 bodies: $(head -c 80 "$tmp/err")" \
    'echo "$cl" | grep -q "^workload=cluster N=20 seed=3 precision=double T=0.05 order=10 tol=1e-12 steps=[1-9][0-9]* cpu_seconds_median=[0-9.]* cpu_seconds_min=[0-9.]* abs_dE=" && [ "$(awk "NF == 7" "$tmp/ic.txt" | wc -l)" -eq 20 ]'
# the eccentric two-body orbit and the Pythagorean problem (issue 37's accuracy against IAS15): the
# default order for the tolerance, the bodies for IAS15, and errors a Taylor run of that
# tolerance reaches (two periods at e = 0.9: below 1e-12; T = 1: below 1e-12)
kp=$("$nbench" kepler 0.9 2 0 1e-14 "$tmp/kic.txt" 2>"$tmp/err")
check "bench_nbody kepler reports steps, CPU time and |dE| and writes the 2 bodies: $(head -c 80 "$tmp/err")" \
    'echo "$kp" | grep -q "^workload=kepler e=0.9 periods=2 precision=double T=12.5601 order=18 tol=1e-14 steps=[1-9][0-9]* cpu_seconds_median=[0-9.]* cpu_seconds_min=[0-9.]* abs_dE=[0-9.]*e-1[2-9]" && [ "$(awk "NF == 7" "$tmp/kic.txt" | wc -l)" -eq 2 ]'
# FINAL and THETA: the bodies at the end, and the orbit turned by pi/2 (pericentre on the y axis)
"$nbench" kepler 0.9 1 0 1e-14 "$tmp/kic2.txt" "$tmp/kfin.txt" 1.5707963267948966 > /dev/null 2>"$tmp/err"
check "bench_nbody kepler THETA turns the orbit and FINAL writes the bodies at the end: $(head -c 80 "$tmp/err")" \
    'awk "NR == 2 { exit !(\$2 * \$2 < 1e-30 && \$3 > 0.0999 && \$3 < 0.1) }" "$tmp/kic2.txt" && [ "$(awk "NF == 7" "$tmp/kfin.txt" | wc -l)" -eq 2 ] && ! cmp -s "$tmp/kic2.txt" "$tmp/kfin.txt"'
py=$("$nbench" pythagorean 1 0 1e-14 "$tmp/pic.txt" 2>"$tmp/err")
check "bench_nbody pythagorean reports steps, CPU time and |dE| and writes the 3 bodies: $(head -c 80 "$tmp/err")" \
    'echo "$py" | grep -q "^workload=pythagorean precision=double T=1 order=18 tol=1e-14 steps=[1-9][0-9]* cpu_seconds_median=[0-9.]* cpu_seconds_min=[0-9.]* abs_dE=[0-9.]*e-1[2-9]" && [ "$(awk "NF == 7" "$tmp/pic.txt" | wc -l)" -eq 3 ]'
wh=$("$nbench" wh data/outer_solar_system.dat 100 0.5 17 4 "$tmp/whic.txt" "$tmp/whcurve.txt" 2>"$tmp/err")
check "bench_nbody wh reports ns per step and |dE| (bounded: below 1e-8 with corrector 17) and writes the 6 bodies and 4 samples: $(head -c 80 "$tmp/err")" \
    'echo "$wh" | grep -q "^workload=wh precision=double years=100 dt_years=0.5 corrector=17 samples=4 steps=200 cpu_seconds_median=[0-9.]* cpu_seconds_min=[0-9.]* ns_per_step=[0-9.]* max_abs_dE=[0-9.]*e-\(09\|1[0-9]\) abs_dE_end=" && [ "$(awk "NF == 7" "$tmp/whic.txt" | wc -l)" -eq 6 ] && [ "$(awk "NF == 2" "$tmp/whcurve.txt" | wc -l)" -eq 4 ]'
cbench="$(dirname "$bench")/bench_charging"
cb=$("$cbench" b1 2e4 2 2>"$tmp/err")
check "bench_charging b1 reports traces per second and the hit fraction: $(head -c 80 "$tmp/err")" \
    'echo "$cb" | grep -q "^workload=b1 triangles=9800 R_gen=3 histories=20000 threads=2 ranks=1 seconds=[0-9.]* traces_per_s=[0-9.e+]* per_thread=[0-9.e+]* hit_fraction=0.1"'
check "bench_charging b1 prints the plain Embree loop's rate beside mote's: $(head -c 80 "$tmp/err")" \
    'echo "$cb" | grep -q " plain_per_thread=[0-9.e+]* plain_hit_fraction=0.1[0-9]* mote_over_plain=[0-9.]*$"'
cb=$("$cbench" b3 2e3 2 2>"$tmp/err")
check "bench_charging b3 reports curved paths: $(head -c 80 "$tmp/err")" \
    'echo "$cb" | grep -q "^workload=b3 triangles=9800 R_gen=3 histories=8000 threads=2 ranks=1 .* steps_per_history=[0-9.]* lost=0 max_energy_err="'
cb=$("$cbench" craft examples/data/spacecraft.obj 1 2e4 2>"$tmp/err")
check "bench_charging craft: the spacecraft, its triangles cut in four, against the plain loop: $(head -c 80 "$tmp/err")" \
    'echo "$cb" | grep -q "^workload=craft triangles=1248 .* walk=0 plain_per_thread=[0-9.e+]* plain_hit_fraction=0.1[0-9]* mote_over_plain=[0-9.]*$"'
"$cbench" nosuch >/dev/null 2>"$tmp/err"
rc=$?
check "bench_charging: an unknown workload fails (exit $rc)" '[ $rc -ne 0 ] && grep -q "usage: bench_charging" "$tmp/err"'
"$nbench" nosuch >/dev/null 2>"$tmp/err"
rc=$?
check "bench_nbody: an unknown workload fails (exit $rc)" '[ $rc -ne 0 ] && grep -q "usage: bench_nbody" "$tmp/err"'

sbench="$(dirname "$bench")/bench_separator"
sb=$("$sbench" ref2d 300 5 2>"$tmp/err")
check "bench_separator ref2d reports steps per second and bytes per particle: $(head -c 80 "$tmp/err")" \
    'echo "$sb" | grep -q "^workload=ref2d N=[0-9]* steps=5 dt=[0-9.e-]* steps_per_s=[0-9.]* ns_per_particle_step=[0-9.]* candidates_per_particle=[0-9.]* contacts_per_particle=[0-9.]* bytes_per_particle=[0-9]* peak_rss_MB="'
sb=$("$sbench" scan2d 600 2>"$tmp/err")
check "bench_separator scan2d compares cells and brute force on the same contacts: $(head -c 80 "$tmp/err")" \
    '[ "$(echo "$sb" | grep -c "same_contacts=yes")" -eq 3 ] && echo "$sb" | grep -q "^workload=scan2d_summary largest_N_at_30_steps_per_s cells=[0-9]* brute=[0-9]*"'
sb=$("$sbench" column 500 5 2 2>"$tmp/err")
check "bench_separator column prints what LIGGGHTS needs: $(head -c 80 "$tmp/err")" \
    'echo "$sb" | grep -q "^workload=column N=[0-9]* box=0.04x0.04x[0-9.]* khat=523599 k_pair=1047.2 dt=4.44288e-06 steps=5 .* threads=2$"'
# the polydisperse column: its line, and the constants per type pair that bench/liggghts_poly.in
# gives LIGGGHTS are the ones the benchmark computes
sb=$("$sbench" poly 1000 5 2 2>"$tmp/err")
pin="$(dirname "$0")/../bench/liggghts_poly.in"
kn_in=$(sed -n '/property\/global kn /,/^fix m2/p' "$pin" | grep -v '^fix m2' | tr -d '&' | tr -s ' \n' ' ' | sed 's/.*peratomtypepair 5 //; s/ *$//')
gn_in=$(sed -n '/property\/global gamman /,/^fix m4/p' "$pin" | grep -v '^fix m4' | tr -d '&' | tr -s ' \n' ' ' | sed 's/.*peratomtypepair 5 //; s/ *$//')
check "bench_separator poly runs on 2 threads: $(head -c 80 "$tmp/err")" \
    'echo "$sb" | grep -q "^workload=poly N=[0-9]* box=0.06x0.06x[0-9.]* khat=523599 dt=2.38088e-06 steps=5 .* threads=2$"'
check "bench/liggghts_poly.in's k_n per type pair are bench_separator poly's" \
    '[ -n "$kn_in" ] && [ "$(echo "$sb" | sed -n "s/^liggghts_kn //p")" = "$kn_in" ]'
check "bench/liggghts_poly.in's gamma_n per type pair are bench_separator poly's" \
    '[ -n "$gn_in" ] && [ "$(echo "$sb" | sed -n "s/^liggghts_gamman //p")" = "$gn_in" ]'
# bench/scaling.sh: its table, from a build without the benchmarks a clear message
sc=$(sh "$(dirname "$0")/../bench/scaling.sh" /nonexistent 2>&1)
check "bench/scaling.sh: a build directory that does not exist is named" 'echo "$sc" | grep -q "nonexistent"'
"$sbench" nosuch >/dev/null 2>"$tmp/err"
rc=$?
check "bench_separator: an unknown workload fails (exit $rc)" '[ $rc -ne 0 ] && grep -q "unknown workload" "$tmp/err"'

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
