#!/bin/sh
# test_galactica.sh: Galactica jobs (spec 7, issue 24) through `mote galactica` and `run galactica`,
# on copies of the job folders in examples/galactica: the document's read-back times (T04) and
# the ring errors (T05, T07), the monitor blocks (T22), the trajectory files (T21), dice.dat (T20,
# its Galactica part), result files, cycles, checkpoints and relaunches (T16), the area (Kl1 = 0),
# pictures, and every refused job: located message, ErrGlctca code, earlier files untouched.
# Usage: sh tests/test_galactica.sh [BUILD_DIR]   (default: build)
NAME=galactica
EX=$(cd "$(dirname "$0")/.." && pwd)/examples/galactica
. "$(dirname "$0")/lib.sh"
mote_test_start "$1"

# set LINE VALUE FILE: put VALUE at column 60 of line LINE of a control file
set_line() {
    awk -v n="$1" -v v="$2" 'NR == n { d = substr($0, 1, 59); $0 = sprintf("%-59s%s", d, v) } { print }' "$3" > "$3.new" && mv "$3.new" "$3"
}
# job DIR: a fresh copy of the 30-body ring job
job() {
    rm -rf "$1" && mkdir "$1" && cp "$EX/ring30/galacf26.dat" "$EX/ring30/axsymb30.dat" "$EX/ring30/check.mote" "$1/"
}
# T of a result file: its first number
tval() { awk 'NR == 1 { print $1; exit }' "$1"; }

# ---- the ring job of Appendix 1 ----------------------------------------------------------------
job ring
(cd ring && "$MOTE" galactica > out.txt 2> err.txt) && ok || bad "ring job failed: $(cat ring/err.txt)"
[ "$(tval ring/garez28.dat)" = "9.9990009999999987E-03" ] && ok || bad "T04: T = $(tval ring/garez28.dat), expected 9.9990009999999987E-03"
grep -q '^   9.999000999999999E-03' ring/out.txt && ok || bad "the last monitor block does not print T = 9.999000999999999E-03 (the document's print)"
(cd ring && "$MOTE" run check.mote > chk.txt 2>&1) && ok || bad "check.mote failed: $(cat ring/chk.txt)"
e=$(sed -n 's/^check ring:.*error \([^,]*\),.*/\1/p' ring/chk.txt)
awk -v e="$e" 'BEGIN { exit !(e != "" && e + 0 <= 1e-12) }' && ok || bad "T05: ring error '$e' above 1e-12"
# T22: a block of 19 values (7 lines: 3, 3, 3, 3, 3, 3, 1) after step 1, then every Kl3 = 1000
blocks=$(awk '/^$/ { n++ } END { print n }' ring/out.txt)
[ "$blocks" -eq 11 ] && ok || bad "T22: $blocks monitor blocks, expected 11 (step 1 and every 1000 steps)"
awk '/^$/ { getline; print; exit }' ring/out.txt | grep -q '^   1.000000000000000E-09 ' && ok || bad "T22: the first block is not after the first step (T = 0.001 dT = 1e-9)"
awk '/^$/ { b = 1; k = 0; next } b && /^ / { k++; w[k] = NF } END { exit !(k == 7 && w[1] == 3 && w[6] == 3 && w[7] == 1) }' ring/out.txt && ok || bad "T22: a block is not 7 lines of 3, 3, 3, 3, 3, 3, 1 values"
last_lt=$(awk '/^$/ { for (i = 0; i < 6; i++) getline; lt = $2 } END { print lt }' ring/out.txt)
[ "$last_lt" = "10000" ] && ok || bad "T22: Lt of the last block is '$last_lt', expected 10000 (the 17th value, an integer)"
# T21: Kli = 10 over 10000 steps = 1000 records of 3 (Kl15 + 1) Np + 2 = 8 numbers; Klmax = 400
for f in 1t 2t; do
    [ "$(wc -l < ring/$f)" -eq 400 ] && ok || bad "T21: $f has $(wc -l < ring/$f) records, expected Klmax = 400"
    awk 'NF != 8 { exit 1 }' ring/$f && ok || bad "T21: a record of $f is not 8 numbers"
done
[ ! -e ring/3t ] && ok || bad "T21: a third file 3t (1000 records fill two files of 400)"
[ "$(wc -l < ring/traekt.prn)" -eq 201 ] && ok || bad "T21: traekt.prn has $(wc -l < ring/traekt.prn) lines, expected 200 records and the summary"
awk 'END { exit !(NF == 10 && $1 == "9.9990009999999987E-03" && $6 == "3.0000000000000000E+01" && $7 + 0 == 0) }' ring/traekt.prn && ok || bad "T21: the summary line: $(tail -1 ring/traekt.prn)"
# the first record is at Lt = 10: T = 0.001 dT + 9 dT
awk 'NR == 1 { exit !($1 + 0 > 9.0009e-6 && $1 + 0 < 9.0011e-6) }' ring/1t && ok || bad "T21: the first record's T is $(head -c 24 ring/1t), expected 9.001e-06 (step 10)"
# body kpp(1) = 1 sits at the barycentre's side: its x is tiny; body kpp(2) = 2 is on the ring
awk 'NR == 1 { exit !($3 * $3 < 1e-8 && $6 * $6 > 1e-5) }' ring/1t && ok || bad "T21: the columns are not body 1's then body 2's positions"
# dice.dat: Ltk Ltk2 / Kl3 = 10 lines (time, body, distance) for Nbd = 2
[ "$(wc -l < ring/dice.dat)" -eq 10 ] && ok || bad "dice.dat has $(wc -l < ring/dice.dat) lines, expected 10"
awk 'NF != 3 || $2 != int($2) || $2 < 1 || $2 > 30 || $2 == 2 || $3 <= 0 { exit 1 }' ring/dice.dat && ok || bad "dice.dat: a line is not time, another body, distance"
# the neighbours of a ring body are bodies 3 and 30, at 2 r sin(pi/29) of the ring radius
awk '{ if ($2 != 3 && $2 != 30) exit 1 }' ring/dice.dat && ok || bad "dice.dat: the closest body to 2 is not a ring neighbour (3 or 30)"
# result files 1 ... 10, the last the same state as garez28.dat
[ -e ring/1 ] && [ -e ring/10 ] && [ ! -e ring/11 ] && ok || bad "result files: expected 1 ... 10"
cmp -s ring/10 ring/garez28.dat && ok || bad "the result file 10 (step 10000) differs from garez28.dat"
[ "$(tval ring/1)" = "9.9900100000000001E-04" ] && ok || bad "result file 1 at T = $(tval ring/1), expected step 1000"

# ---- cycles: Ltk = 2500 x Ltk2 = 4 is the same run as 10000 x 1 -------------------------------
job cyc
set_line 24 2500 cyc/galacf26.dat
set_line 25 4 cyc/galacf26.dat
(cd cyc && "$MOTE" galactica > out.txt 2> err.txt) && ok || bad "cycles job failed: $(cat cyc/err.txt)"
sed '$d' cyc/garez28.dat > a.txt; sed '$d' ring/garez28.dat > b.txt
cmp -s a.txt b.txt && ok || bad "Ltk 2500 x Ltk2 4 differs from Ltk 10000 x Ltk2 1"

# ---- T16: checkpoints (Kl1 = 4) and relaunches --------------------------------------------------
job whole
set_line 26 4 whole/galacf26.dat
set_line 24 2000 whole/galacf26.dat
set_line 31 500 whole/galacf26.dat
(cd whole && "$MOTE" galactica > out.txt 2> err.txt) && ok || bad "the 2000-step job failed: $(cat whole/err.txt)"
[ -e whole/galgon4 ] && ok || bad "Kl1 = 4 wrote no galgon4"
job half
set_line 26 4 half/galacf26.dat
set_line 24 1000 half/galacf26.dat
set_line 31 500 half/galacf26.dat
(cd half && "$MOTE" galactica > out.txt 2> err.txt) && ok || bad "the first 1000 steps failed: $(cat half/err.txt)"
cp half/garez28.dat half1.dat
# a relaunch reads neither the control file nor axsymb30.dat: break both to prove it
printf 'this is not a control file\n' > half/galacf26.dat.bad
mv half/axsymb30.dat half/axsymb30.away
(cd half && "$MOTE" galactica > out2.txt 2> err.txt) && ok || bad "the relaunch failed: $(cat half/err.txt)"
grep -q 'resuming from galgon4 at step 1000' half/out2.txt && ok || bad "the relaunch did not resume at step 1000: $(head -3 half/out2.txt)"
sed '$d' half/garez28.dat > a.txt; sed '$d' whole/garez28.dat > b.txt
cmp -s a.txt b.txt && ok || bad "T16: 1000 + checkpoint + 1000 steps differ from 2000 steps"
cmp -s half/traekt.prn whole/traekt.prn && ok || bad "T16: the trajectory of the resumed run differs"
cmp -s half/dice.dat whole/dice.dat && ok || bad "T16: dice.dat of the resumed run differs"
[ -e half/4 ] && [ ! -e half/5 ] && cmp -s half/4 whole/4 && ok || bad "T16: the result files do not continue their numbering (1 ... 4) identically"
# continuation from the text file (Kl1 = 1, Kl4 = 1): agrees to 1e-14 (no compensation terms)
job cont
cp half1.dat cont/garez28.dat
set_line 26 1 cont/galacf26.dat
set_line 27 1 cont/galacf26.dat
set_line 24 1000 cont/galacf26.dat
(cd cont && "$MOTE" galactica > out.txt 2> err.txt) && ok || bad "the continuation from garez28.dat failed: $(cat cont/err.txt)"
# (differences in positions and in velocities, over the largest position and speed)
awk 'NR == FNR { if (FNR > 2 && NF == 15) for (k = 2; k <= 7; k++) a[FNR, k] = $k; next }
     FNR > 2 && NF == 15 { for (k = 2; k <= 7; k++) { g = k < 5; d = $k - a[FNR, k]; s = $k; if (d < 0) d = -d; if (s < 0) s = -s; if (d > dm[g]) dm[g] = d; if (s > sm[g]) sm[g] = s } }
     END { m = dm[0] / sm[0]; if (dm[1] / sm[1] > m) m = dm[1] / sm[1]; printf "%.3g\n", m; exit !(m <= 1e-14) }' whole/garez28.dat cont/garez28.dat > rel.txt && ok || bad "T16: the continuation from garez28.dat differs by $(cat rel.txt) (relative), above 1e-14"
# a finished checkpointed job relaunched adds a block of Ltk Ltk2 steps
(cd whole && "$MOTE" galactica > out2.txt 2> err.txt) && ok || bad "relaunch of a finished job failed: $(cat whole/err.txt)"
grep -q '2000 steps (Lt 2000 to 4000)' whole/out2.txt && ok || bad "a finished job's relaunch did not add 2000 steps: $(grep steps whole/out2.txt | head -2)"

# ---- the area (Kl1 = 0) with pictures ----------------------------------------------------------
job area
set_line 26 0 area/galacf26.dat
set_line 24 200 area/galacf26.dat
set_line 31 100 area/galacf26.dat
set_line 7 2 area/galacf26.dat
set_line 22 5.E-4 area/galacf26.dat
set_line 2 1. area/galacf26.dat
set_line 3 1. area/galacf26.dat
set_line 9 2. area/galacf26.dat
set_line 10 1.5 area/galacf26.dat
set_line 11 0.5 area/galacf26.dat
set_line 12 0.5 area/galacf26.dat
set_line 13 -0.4 area/galacf26.dat
set_line 16 0.3 area/galacf26.dat
set_line 28 28 area/galacf26.dat
set_line 46 300. area/galacf26.dat
set_line 47 300. area/galacf26.dat
set_line 39 3. area/galacf26.dat
rm area/axsymb30.dat
(cd area && "$MOTE" galactica --frames > out.txt 2> err.txt) && ok || bad "the area job failed: $(cat area/err.txt)"
grep -q 'the area, 3 x 3 x 3 bodies and the separate body' area/out.txt && ok || bad "the area: $(grep area area/out.txt)"
awk 'NR == 2 { exit !($3 == 3 && $4 == 3 && $5 == 3 && $9 == 2) }' area/garez28.dat && ok || bad "the area's header fields i2b j2b k2b Mu: $(sed -n 2p area/garez28.dat)"
[ "$(awk 'NR > 2 && NF == 15' area/garez28.dat | wc -l)" -eq 28 ] && ok || bad "the area's result has $(awk 'NR > 2 && NF == 15' area/garez28.dat | wc -l) bodies, expected 28"
# pictures: after step 1, at 100, 200 (the end): three 1024 x 768 PNGs
ls area/frame_00000[0-2].png > /dev/null 2>&1 && [ ! -e area/frame_000003.png ] && ok || bad "frames: $(ls area | grep frame | tr '\n' ' ')"
[ "$(od -An -tu1 -j16 -N8 area/frame_000002.png | awk '{ print $3*256+$4, $7*256+$8 }')" = "1024 768" ] && ok || bad "a frame is not 1024 x 768"

# ---- run galactica in a script: the final system stays for later commands -----------------------
job scr
cat > scr/job.mote <<'EOF'
model nbody gravity
units solar
generate ring nb=30
run galactica
check ring
EOF
(cd scr && rm -f garez28.dat && "$MOTE" run job.mote > out.txt 2> err.txt) && ok || bad "run galactica failed: $(cat scr/err.txt)"
grep -q '^check ring: T = 0.0099990009999999987 ' scr/out.txt && ok || bad "check ring after run galactica: $(grep '^check' scr/out.txt)"
sed '$d' scr/garez28.dat > a.txt; sed '$d' ring/garez28.dat > b.txt
cmp -s a.txt b.txt && ok || bad "run galactica and mote galactica differ"

# ---- the Coulomb ring of Appendix 3 ------------------------------------------------------------
rm -rf atom && mkdir atom && cp "$EX/atom9/galacf26.dat" "$EX/atom9/axsykl09.dat" "$EX/atom9/check.mote" atom/
(cd atom && "$MOTE" galactica --coulomb > out.txt 2> err.txt) && ok || bad "the Coulomb job failed: $(cat atom/err.txt)"
[ "$(tval atom/garek29.dat)" = "2.9999900099999997E-02" ] && ok || bad "T04: Coulomb T = $(tval atom/garek29.dat), expected 2.9999900099999997E-02"
(cd atom && "$MOTE" run check.mote > chk.txt 2>&1) && ok || bad "atom check.mote failed"
e=$(sed -n 's/^check ring:.*error \([^,]*\),.*/\1/p' atom/chk.txt)
awk -v e="$e" 'BEGIN { exit !(e != "" && e + 0 <= 1e-11) }' && ok || bad "T07: Coulomb ring error '$e' above 1e-11"
# the wrong module: the masses give it away
rm -rf atom2 && mkdir atom2 && cp "$EX/atom9/galacf26.dat" "$EX/atom9/axsykl09.dat" atom2/
(cd atom2 && "$MOTE" galactica > out.txt 2> err.txt); rc=$?
[ $rc -eq 1 ] && ok || bad "a Coulomb file run as gravity: exit $rc, expected 1"
grep -q 'axsykl09.dat: .*is it a Coulomb (25/16 layout) file' atom2/err.txt && ok || bad "a Coulomb file run as gravity: $(cat atom2/err.txt)"

# ---- refused jobs: a located message, ErrGlctca, and nothing of the earlier run touched ----------
# refused DIR STATUS CODE TEXT [OPTIONS]: run, then check status, message, ErrGlctca, garez28.dat
refused() {
    d=$1 st=$2 code=$3 text=$4
    shift 4
    (cd "$d" && "$MOTE" galactica "$@" > out.txt 2> err.txt); rc=$?
    [ $rc -eq "$st" ] && ok || bad "$d: exit $rc, expected $st ($(cat "$d/err.txt"))"
    grep -qF -- "$text" "$d/err.txt" && ok || bad "$d: stderr '$(cat "$d/err.txt")', expected '$text'"
    grep -q "^\*${code}G " "$d/ErrGlctca" && ok || bad "$d: ErrGlctca has no *${code}G line: $(cat "$d/ErrGlctca" 2>/dev/null)"
    cmp -s "$d/garez28.dat" earlier.dat && ok || bad "$d: the earlier garez28.dat was changed"
}
printf 'an earlier result\n' > earlier.dat
for t in kl1 k2 np kpp body missing bt many; do job $t; cp earlier.dat $t/garez28.dat; done
set_line 26 7 kl1/galacf26.dat
refused kl1 1 02 "galacf26.dat:26: Kl1 = 7, expected 0 (area)"
set_line 30 31 k2/galacf26.dat
refused k2 1 02 "axsymb30.dat"
set_line 49 5 np/galacf26.dat
refused np 1 02 "galacf26.dat:49: Np = 5, expected 1 ... 2"
set_line 57 31 kpp/galacf26.dat
refused kpp 1 02 "kpp(2) = 31 (the body of trajectory column 2), expected 1 ... 30"
sed '5s/.*/1.0 2.0 x 4.0/' ring/garez28.dat > body/axsymb30.dat
refused body 1 02 "axsymb30.dat:5"
rm missing/axsymb30.dat
refused missing 1 01 "axsymb30.dat: cannot open"
set_line 40 1.5 bt/galacf26.dat
refused bt 1 02 "galacf26.dat:40: bt = 1.5"
set_line 34 1 many/galacf26.dat
set_line 23 1 many/galacf26.dat
refused many 1 12 "above the limit of 10000"
[ ! -e many/1t ] && ok || bad "a refused job wrote trajectory files"
(cd many && "$MOTE" galactica --max-files 20000 > out.txt 2> err.txt) && ok || bad "--max-files 20000 did not let the job run: $(cat many/err.txt)"
# a step of 1e308 (issue 33): the state stops being finite in step 1; the job stops there, and
# no result file holds INF or NAN
job inf; cp earlier.dat inf/garez28.dat
set_line 26 0 inf/galacf26.dat
set_line 22 1.E308 inf/galacf26.dat
refused inf 2 02 "integrate: the state stopped being finite in step 1"
[ ! -e inf/1 ] && ! grep -qi 'nan\|inf' inf/garez28.dat && ok || bad "a job that stopped being finite wrote results"
rm -rf noctl && mkdir noctl
(cd noctl && "$MOTE" galactica > out.txt 2> err.txt); rc=$?
[ $rc -eq 1 ] && grep -q 'galacf26.dat: cannot open' noctl/err.txt && grep -q '^\*01G ' noctl/ErrGlctca && ok || bad "no control file: exit $rc, $(cat noctl/err.txt)"
(cd noctl && "$MOTE" galactica --threads x > out.txt 2> err.txt); rc=$?
[ $rc -eq 1 ] && grep -q -- '--threads needs a count' noctl/err.txt && ok || bad "bad --threads: exit $rc, $(cat noctl/err.txt)"
"$MOTE" galactica --help | grep -q '^Usage: mote galactica' && ok || bad "mote galactica --help"
# a damaged checkpoint is refused with its line, and a Kl1 = 2 control file ignores it
job ck
set_line 26 4 ck/galacf26.dat
set_line 24 100 ck/galacf26.dat
set_line 31 50 ck/galacf26.dat
(cd ck && "$MOTE" galactica > /dev/null 2>&1) && ok || bad "ck: the first launch failed"
sed -i 's/^counters .*/counters 1 2 x/' ck/galgon4
(cd ck && "$MOTE" galactica > out.txt 2> err.txt); rc=$?
[ $rc -eq 1 ] && grep -q 'galgon4:[0-9]*: files: expected a non-negative integer' ck/err.txt && ok || bad "a damaged checkpoint: exit $rc, $(cat ck/err.txt)"
set_line 26 2 ck/galacf26.dat
(cd ck && "$MOTE" galactica > out.txt 2> err.txt) && ! grep -q resuming ck/out.txt && ok || bad "Kl1 = 2 did not start afresh beside a checkpoint: $(cat ck/err.txt)"

# checkpoint edit: the next launch runs the new Ltk * Ltk2 steps with the new dT
job ed
set_line 26 4 ed/galacf26.dat
set_line 24 100 ed/galacf26.dat
set_line 31 50 ed/galacf26.dat
(cd ed && "$MOTE" galactica > /dev/null 2>&1 && "$MOTE" galactica edit Ltk=300 dT=2e-6 Kl3=100 > out.txt 2> err.txt) && ok || bad "galactica edit failed: $(cat ed/err.txt)"
grep -q 'plans steps 100 to 400, dT = 1.9999999999999999E-06' ed/out.txt && ok || bad "galactica edit: $(cat ed/out.txt)"
(cd ed && "$MOTE" galactica > out.txt 2> err.txt) && ok || bad "the launch after edit failed: $(cat ed/err.txt)"
awk 'NR == 1 { t = $1 + 0 } NR == 2 { exit !(t > 6.99000e-4 && t < 6.99002e-4 && $2 == "1.9999999999999999E-06") }' ed/garez28.dat && ok || bad "after edit: T = $(tval ed/garez28.dat), expected 9.9001e-5 + 300 x 2e-6"
[ "$(grep -c '^$' ed/out.txt)" -eq 3 ] && ok || bad "after edit: $(grep -c '^$' ed/out.txt) monitor blocks, expected 3 (Kl3 = 100: steps 200, 300, 400)"
(cd ed && "$MOTE" galactica edit Mu=3 > out.txt 2> err.txt); rc=$?
[ $rc -eq 1 ] && grep -q "'Mu=3': expected KEY=VALUE with KEY one of Ltk" ed/err.txt && ok || bad "edit of a fixed value: exit $rc, $(cat ed/err.txt)"
(cd ed && "$MOTE" galactica edit Nbd=31 > out.txt 2> err.txt); rc=$?
[ $rc -eq 1 ] && grep -q "Nbd = 31, expected 0 (off) or a body 1 ... 30" ed/err.txt && ok || bad "edit Nbd=31: exit $rc, $(cat ed/err.txt)"

# ---- T20: approaches with in-step refinement, on a two-body hyperbolic flyby ---------------------
# G = 1, masses 0.75 and 0.25, relative orbit e = 2 with periapsis q = 0.1, started at true
# anomaly -2 rad; Kepler's hyperbolic equation gives the periapsis time t_p = 0.50111018402362074
# and speed v_p = sqrt(3 / 0.1); the flyby's time scale q / v_p = 0.0182574 (mpmath, 40 digits).
fly() {
    printf 'model nbody gravity\nunits dimensionless\n'
    printf 'body mass=0.75 x=0.18610515963767164217 y=0.40664719256696120834 vx=-0.41503559346152418213 vy=-0.72292675449920588968\n'
    printf 'body mass=0.25 x=-0.55831547891301492651 y=-1.219941577700883625 vx=1.2451067803845725464 vy=2.168780263497617669\n'
    printf '%s\napproaches body=1 every=1000000 %s file=%s\nintegrate to=1\n' "$1" "$2" "$3"
}
fly 'integrator taylor order=20 tol=1e-16' refine=on fly.dat > fly.mote
fly 'integrator taylor order=20 tol=1e-16' refine=off fly0.dat > fly0.mote
fly 'integrator galactica dt=1e-4' refine=on flyg.dat > flyg.mote
for f in fly fly0 flyg; do "$MOTE" run $f.mote > out.txt 2> err.txt && ok || bad "$f.mote failed: $(cat err.txt)"; done
grep -q '^# columns: T_min body distance relative_speed$' fly.dat && ok || bad "approaches: the columns"
awk '!/^#/ { dt = $1 - 0.50111018402362074; if (dt < 0) dt = -dt; dq = ($3 - 0.1) / 0.1; if (dq < 0) dq = -dq
             exit !($2 == 2 && dt <= 1e-10 * 0.0182574 && dq <= 1e-10) }' fly.dat && ok || bad "T20: the refined minimum (Taylor) is off: $(tail -1 fly.dat)"
awk '!/^#/ { dt = $1 - 0.50111018402362074; if (dt < 0) dt = -dt; dq = ($3 - 0.1) / 0.1; if (dq < 0) dq = -dq
             exit !($2 == 2 && dt <= 1e-10 * 0.0182574 && dq <= 1e-10) }' flyg.dat && ok || bad "T20: the refined minimum (Galactica scheme, dt 1e-4) is off: $(tail -1 flyg.dat)"
awk '!/^#/ { exit !($3 >= 0.1 && $3 > 0.1000001) }' fly0.dat && ok || bad "T20: the sampled minimum is not above the true one: $(tail -1 fly0.dat)"
expect 1 "ap1.mote:3:" ap1.mote 'model nbody gravity\nbody mass=1\napproaches body=1 every=10 file=a.dat refine=yes\n'
expect 1 "ap2.mote:3:" ap2.mote 'model nbody gravity\nbody mass=1\napproaches body=4 every=10 file=a.dat\n'

# ---- forces tree in scripts: labelled approximate wherever written --------------------------------
printf 'model nbody gravity\ngenerate plummer n=500 seed=3\nforces tree theta=0.5\nintegrator galactica dt=1e-3\nmonitor every=5 file=t.mon\nintegrate steps=10\nwrite snapshot file=t.snap\nforces direct\nintegrate steps=2\nwrite snapshot file=d.snap\n' > tree.mote
"$MOTE" run tree.mote > out.txt 2> err.txt && ok || bad "tree.mote failed: $(cat err.txt)"
grep -q '^# forces = tree$' t.snap && grep -q '^# theta = 0.5$' t.snap && grep -q '^# approximate: Barnes-Hut' t.snap && ok || bad "a snapshot of a tree run is not labelled: $(grep '^# forces\|^# theta\|^# approx' t.snap)"
grep -q '^# approximate: some steps of this run used Barnes-Hut tree forces' t.mon && ok || bad "the monitor of a run that used the tree is not labelled"
grep -q '^# approximate: some steps of this run used Barnes-Hut tree forces' d.snap && ok || bad "a later direct snapshot forgets the tree steps"
[ "$(grep -vc "^#" t.mon)" -eq 3 ] && ok || bad "tree monitor rows: $(grep -vc "^#" t.mon), expected steps 0, 5, 10"
expect 1 "tr1.mote:2:" tr1.mote 'model nbody gravity\nforces direct theta=0.3\n'
expect 1 "tr2.mote:2:" tr2.mote 'model nbody gravity\nforces tree theta=3\n'
expect 1 "tr3.mote:2:" tr3.mote 'model nbody gravity\nforces fmm\n'
expect 1 "tr4.mote:2:" tr4.mote 'model nbody gravity\ngenerate plummer seed=2\n'
expect 1 "tr5.mote:2:" tr5.mote 'model nbody coulomb\ngenerate plummer n=10\n'
expect 2 "tr6.mote:5:1: error: forces tree: the charges have both signs" tr6.mote 'model nbody coulomb\nbody mass=0.5 charge=1\nbody mass=0.5 charge=-1 x=1\nforces tree\nintegrate steps=1\n'
# generate area in a script: the header's area fields, and its errors
printf 'model nbody gravity\ngenerate area mu=2 b=0.5 c=0.5 sep_density=2 sep_pos=1.5,0.5,0.5 sep_vel=-0.4,0,0 omega=0.3\nwrite galactica file=a.dat\n' > area.mote
"$MOTE" run area.mote > out.txt 2> err.txt && ok || bad "generate area failed: $(cat err.txt)"
awk 'NR == 2 { exit !($3 == 3 && $4 == 2 && $5 == 2 && $7 == "5.0000000000000000E-01" && $9 == 2) }' a.dat && ok || bad "generate area: header $(sed -n 2p a.dat)"
[ "$(awk 'NR > 2 && NF == 15' a.dat | wc -l)" -eq 13 ] && ok || bad "generate area: $(awk 'NR > 2 && NF == 15' a.dat | wc -l) bodies, expected 3 x 2 x 2 + 1"
awk 'NR > 2 && NF == 15 { m += $1 } END { exit !(m > 1 - 1e-15 && m < 1 + 1e-15) }' a.dat && ok || bad "generate area: the masses do not sum to 1"
expect 1 "ga1.mote:2:" ga1.mote 'model nbody gravity\ngenerate area mu=2 nb=3\n'
expect 1 "ga2.mote:2:" ga2.mote 'model nbody gravity\ngenerate area origin=1,2\n'
expect 1 "ga3.mote:2:" ga3.mote 'model nbody coulomb\ngenerate area\n'

# ---- frames in a script (spec 7.13): at the command and every K steps, 1024 x 768 ----------------
printf 'model nbody gravity\nunits solar\ngenerate ring nb=6\nframes every=2500 prefix=rf_\nintegrate steps=10000\nframes every=5000 prefix=rc_ control=ring/galacf26.dat\nintegrate steps=10000\n' > fr.mote
"$MOTE" run fr.mote > out.txt 2> err.txt && ok || bad "frames failed: $(cat err.txt)"
[ "$(ls rf_*.png | wc -l)" -eq 5 ] && [ "$(ls rc_*.png | wc -l)" -eq 3 ] && ok || bad "frames: $(ls rf_* rc_* | tr '\n' ' '), expected 5 and 3"
[ "$(od -An -tu1 -j16 -N8 rc_000002.png | awk '{ print $3*256+$4, $7*256+$8 }')" = "1024 768" ] && ok || bad "a frame of the frames command is not 1024 x 768"
cmp -s rf_000000.png rf_000001.png && bad "frames: the pictures at steps 0 and 2500 are the same" || ok
expect 1 "fr1.mote:3:" fr1.mote 'model nbody gravity\nbody mass=1\nframes every=10 control=nothere.dat\n'
# (prefix= makes one missing folder, issue 52; two are an error)
expect 1 "fr3.mote:3:" fr3.mote 'model nbody gravity\nbody mass=1\nframes every=10 prefix=nodir/sub/f_\n'
printf 'A                                                          x\n' > badctl.dat
expect 1 "fr2.mote:3:" fr2.mote 'model nbody gravity\nbody mass=1\nframes every=10 control=badctl.dat\n'

# snapshot format=galactica: result files every K steps, the same layout as write galactica
printf 'model nbody gravity\nunits solar\ngenerate ring nb=6\nsnapshot every=5000 prefix=gs_ format=galactica\nintegrate steps=10000\nwrite galactica file=end.dat\n' > gs.mote
"$MOTE" run gs.mote > out.txt 2> err.txt && ok || bad "snapshot format=galactica failed: $(cat err.txt)"
[ -e gs_0000005000.dat ] && cmp -s gs_0000010000.dat end.dat && ok || bad "snapshot format=galactica: $(ls gs_* | tr '\n' ' ') (the last should equal write galactica)"
# snapshot file= format=galactica: one result file now, the same as write galactica
printf 'model nbody gravity\nunits solar\ngenerate ring nb=30\nintegrate steps=100\nsnapshot file=one.dat format=galactica\nwrite galactica file=two.dat\n' > g1.mote
"$MOTE" run g1.mote > out.txt 2> err.txt && [ -s one.dat ] && cmp -s one.dat two.dat && ok || bad "snapshot file= format=galactica differs from write galactica: $(cat err.txt)"
expect 1 "gs1.mote:3:" gs1.mote 'model nbody gravity\nbody mass=1\nsnapshot every=5 format=xyz\n'

# run galactica's options are checked before anything runs
expect 1 "bad1.mote:2:" bad1.mote 'model nbody gravity\nrun galactica frames=maybe\n'
expect 1 "bad2.mote:2:" bad2.mote 'model nbody gravity\nrun galaxy\n'
job bad3
set_line 27 9 bad3/galacf26.dat
expect 1 "bad3.mote:2:" bad3.mote 'model nbody gravity\nrun galactica control=bad3/galacf26.dat\n'

mote_test_end
