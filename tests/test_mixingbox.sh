#!/bin/sh
# test_mixingbox.sh: the mixing-box model end to end through the `mote` program: bad parameters
# rejected before anything runs with FILE:LINE:COLUMN at the offending argument (or, for the
# geometry, at `place` naming the commands that set it), nothing written by an invalid script,
# a valid run's summary line and files, frames and the movie command with and without ffmpeg,
# a failing run that keeps every recorded sample, and a placement that does not fit.
# Usage: sh tests/test_mixingbox.sh [BUILD_DIR]   (default: build)
NAME=mixingbox
. "$(dirname "$0")/lib.sh"
mote_test_start "$1"

H='model mixing-box\n'

# ranges, at the argument
expect 1 "b1.mote:2:7: error: box: X_R must be above X_L = 0, found -1" b1.mote "${H}box 0 -1 0 1\nplace\n"
expect 1 "b2.mote:2:6: error: loss: LOSS must be in [0, 1], found 1.5" b2.mote "${H}loss 1.5\n"
expect 1 "b3.mote:2:12: error: integrator: expected 'timestep' or 'event' for NAME, found 'fast'" b3.mote "${H}integrator fast\n"
expect 1 "b4.mote:2:16: error: collision_rule: expected 'restitution' or 'seed' for NAME, found 'soft'" b4.mote "${H}collision_rule soft\n"
expect 1 "b5.mote:2:9: error: disks: nLeft + nRight must be at least 1, found 0 + 0" b5.mote "${H}disks 0 0\n"
expect 1 "b6.mote:2:8: error: radius: R must be > 0, found 0" b6.mote "${H}radius 0\n"
expect 1 "b7.mote:2:11: error: kicks: dV_S must be >= 0, found -1" b7.mote "${H}kicks 0 0 -1\n"
expect 1 "b8.mote:2:13: error: partition: a must be > 0, found 0" b8.mote "${H}partition 1 0\n"
expect 1 "b9.mote:2:5: error: t_c: T must be >= 0, found -0.1" b9.mote "${H}t_c -0.1\n"
expect 1 "b10.mote:2:8: error: v_init: V must be in [0, 1e6], found -2" b10.mote "${H}v_init -2\n"
# the geometry, at place, naming the commands that set the values
expect 1 "g1.mote:3:1: error: place: slit: X2_C -/+ b/2 = 0.93, 1.03 must lie inside the box height X_B = 0 .. X_T = 1 [set by: box (default), slit on line 2]" \
    g1.mote "${H}slit 0.98 0.1\nplace\n"
expect 1 "g2.mote:4:1: error: place: slit: the height b = 0.015 must exceed a disk's diameter 2R = 0.02" \
    g2.mote "${H}radius 0.01\nslit 0.5 0.015\nplace\n"
expect 1 "g3.mote:3:1: error: place: partition: its faces X1_C -/+ a/2 = 1.99, 2.01 must lie inside the box" \
    g3.mote "${H}partition 2 0.02\nplace\n"
expect 1 "g4.mote:4:1: error: place: the left chamber is too dense for random placement: 5000 disks of R = 0.01 in 0.99 x 1 give the area fraction n pi R^2 / area = 1.587, above 0.54" \
    g4.mote "${H}radius 0.01\ndisks 5000 10\nplace\n"
expect 1 "g5.mote:4:1: error: place: the right chamber is 0.0055 wide (X_R - X1_R), less than a disk's diameter 2R = 0.01 [set by: box on line 2, partition on line 3, radius (default)]" \
    g5.mote "${H}box 0 2 0 1\npartition 1.9845 0.02\nplace\n"
# order and outputs
expect 1 "o1.mote:2:1: error: run: no disks are placed yet" o1.mote "${H}run 1\n"
expect 1 "o2.mote:3:5: error: run: T must be > 0, found 0" o2.mote "${H}place\nrun 0\n"
expect 1 "o3.mote:3:10: error: snapshot: FILE must end in .png (a picture), .xyz (extended XYZ), .h5 (H5MD) or .vtk (VTK), found 'x.jpg'" o3.mote "${H}place\nsnapshot x.jpg\n"
expect 1 "o4.mote:3:12: error: monitor: the directory of output file 'nodir/m.dat' does not exist" o4.mote "${H}place\nrecord 0.1 nodir/m.dat\n"
expect 1 "o5.mote:2:7: error: movie: no earlier 'frames' writes 'f_000000.png' and it does not exist" o5.mote "${H}movie f 25 m.mp4\n"
expect 1 "o6.mote:2:6: error: plot: 'none.dat' does not exist and no earlier command writes it" o6.mote "${H}plot none.dat x.png\n"
expect 1 "o7.mote:4:5: error: run: 1 s with a frame every 1e-06 s would write 1e+06 PNG files" o7.mote "${H}place\nframes 1e-6 f\nrun 1\n"
expect 1 "o8.mote:2:1: error: monitor: no disks are placed yet" o8.mote "${H}record 1 m.dat\n"
expect 1 "o9.mote:3:18: error: run_collisions: T_MAX must be > 0, found 0" o9.mote "${H}place\nrun_collisions 5 0\n"
expect 1 "o10.mote:4:1: error: run_collisions: there is only one disk, which never collides" o10.mote "${H}disks 1 0\nplace\nrun_collisions 5 1\n"
# an invalid last line: nothing ran, nothing was written
expect 1 "o11.mote:5:6: error: loss:" o11.mote "${H}place\nsnapshot early.png\nrecord 0.1 early.dat\nloss 2\n"
[ ! -e early.png ] && [ ! -e early.dat ] && ok || bad "o11.mote: a file was written by an invalid script"
[ ! -s out.txt ] && ok || bad "o11.mote: something ran: $(cat out.txt)"
# a geometry change after place: a warning, and the script runs
expect 0 "w1.mote:3:1: warning: radius: the disks placed on line 2 keep their geometry; this takes effect at the next 'place'" \
    w1.mote "${H}place\nradius 0.004\n" check

# a valid run: summary line, status line, files, frames; no ffmpeg on PATH
mkdir -p fr nopath
cat > v1.mote <<'EOF'
model mixing-box
integrator timestep
seed 3
radius 0.01
disks 200 200
place
snapshot start.png
snapshot start.xyz
record 0.05 mix.dat
frames 0.05 fr/f
run 0.2
frames_stop
run 0.1
plot mix.dat mix.png
movie fr/f 10 movie.mp4
EOF
PATH="$TMP/nopath" "$MOTE" run v1.mote > out.txt 2> err.txt
st=$?
[ "$st" -eq 0 ] && ok || bad "v1.mote: exit status $st: $(cat err.txt)"
grep -q '^run: t=0.2 .*mixing_fraction=.* E_rel_drift=.* overlaps=[0-9]* ' out.txt && ok || bad "v1.mote: no summary line: $(grep '^run:' out.txt)"
grep -q '^N=400 t=0.3 m=' out.txt && ok || bad "v1.mote: no status line at t = 0.3"
[ -s start.png ] && [ -s mix.dat ] && [ -s mix.png ] && ok || bad "v1.mote: outputs missing: $(ls)"
[ "$(sed -n 1p start.xyz)" = "400" ] && [ "$(grep -Ec '^(He|Ar) ' start.xyz)" -eq 400 ] && ok || bad "v1.mote: start.xyz"
n=$(ls fr | grep -c '^f_00000[0-4]\.png$')
[ "$n" -eq 5 ] && [ "$(ls fr | wc -l)" -eq 5 ] && ok || bad "v1.mote: frames: $(ls fr)"
[ "$(grep -vc '^#' mix.dat)" -eq 7 ] && ok || bad "v1.mote: mix.dat has $(grep -vc '^#' mix.dat) rows, expected 7"
grep -q "note: movie: ffmpeg is not on PATH" err.txt && grep -q "ffmpeg -y -framerate 10 -i 'fr/f_%06d.png'" err.txt && ok || bad "v1.mote: no ffmpeg note: $(cat err.txt)"
[ ! -e movie.mp4 ] && ok || bad "v1.mote: a movie without ffmpeg"

# with an ffmpeg on PATH (a fake one that writes its last argument)
mkdir -p fakebin
printf '#!/bin/sh\nfor a; do last=$a; done\necho "$*" > "$last"\n' > fakebin/ffmpeg
chmod +x fakebin/ffmpeg
printf '%b' "${H}movie fr/f 10 movie.mp4\n" > v2.mote
PATH="$TMP/fakebin:/usr/bin:/bin" "$MOTE" run v2.mote > out.txt 2> err.txt
st=$?
[ "$st" -eq 0 ] && grep -q '^movie: wrote movie.mp4' out.txt && ok || bad "v2.mote: status $st: $(cat out.txt err.txt)"
grep -q -- "-framerate 10 -i fr/f_%06d.png .* -pix_fmt yuv420p movie.tmp[0-9]*.mp4" movie.mp4 && ok || bad "v2.mote: ffmpeg arguments: $(cat movie.mp4)"
[ -z "$(ls | grep '\.tmp')" ] && ok || bad "v2.mote: temporary files left: $(ls)"

# a run that fails at its fourth sample (a directory blocks frame 3): the record keeps the
# samples taken so far, complete; exit status 2, located at the run
mkdir -p fr2/f_000003.png
cat > f1.mote <<'EOF'
model mixing-box
integrator timestep
radius 0.01
disks 100 100
place
record 0.05 keep.dat
frames 0.05 fr2/f
run 0.3
EOF
"$MOTE" run f1.mote > out.txt 2> err.txt
st=$?
[ "$st" -eq 2 ] && ok || bad "f1.mote: exit status $st, expected 2"
grep -q '^f1.mote:8:1: error: .*fr2/f_000003.png' err.txt && ok || bad "f1.mote: error: $(cat err.txt)"
rows=$(grep -vc '^#' keep.dat)
[ "$rows" -eq 4 ] && ok || bad "f1.mote: keep.dat has $rows rows, expected 4"
last=$(tail -n 1 keep.dat)
[ "$(echo "$last" | wc -w)" -eq 21 ] && [ "$(echo "$last" | cut -d' ' -f1)" = "0.15000000000000002" ] && ok || bad "f1.mote: last row '$last'"
grep -q '^# samples = 4$' keep.dat && ok || bad "f1.mote: header sample count"

# disks that do not fit at random (the check's limit passed): exit 2, the density named
printf '%b' "${H}box 0 0.21 0 0.1\npartition 0.105 0.01\nslit 0.05 0.03\nradius 0.01\ndisks 17 1\nplace\n" > f2.mote
"$MOTE" run f2.mote > out.txt 2> err.txt
st=$?
[ "$st" -eq 2 ] && grep -q "^f2.mote:7:1: error: place: disk [0-9]* of 17 in the left chamber did not fit after 1000000 random tries: the chamber is too dense for random placement (area fraction n pi R^2 / area = 0.534" err.txt \
    && ok || bad "f2.mote: status $st: $(cat err.txt)"

# state files: save and load, their faults named with FILE:LINE, nothing changed by a bad load
printf '%b' "${H}disks 5 5\nplace\nrun 0.1\nsave good.state\n" > s0.mote
"$MOTE" run s0.mote > out.txt 2> err.txt && ok || bad "s0.mote: $(cat err.txt)"
grep -q '^placed loss 0$' good.state && grep -q '^next integrator event$' good.state &&
    [ "$(grep -c '^[-0-9.e]* [-0-9.e]* [-0-9.e]* [-0-9.e]* [01] [01] ' good.state)" -eq 10 ] &&
    ok || bad "good.state: $(head -n 12 good.state)"
expect 1 "s1.mote:2:6: error: load: 'none.state' does not exist and no earlier command writes it" s1.mote "${H}load none.state\n"
expect 1 "s2.mote:2:1: error: run: no disks are placed yet" s2.mote "${H}run 1\nload good.state\n"
expect 1 "s3.mote:2:1: error: save: no disks are placed yet" s3.mote "${H}save x.state\n"
# a hard-sphere state is another model's
printf 'new 2 0.3\nsave hs.state\n' > hs.mote
"$MOTE" run hs.mote > /dev/null 2>&1
expect 1 "s4.mote:2:6: error: load: hs.state:2: expected 'model mixing-box' (a state of the mixing-box model; found 'model hard-spheres')" s4.mote "${H}load hs.state\n"
# faults in the disk lines are found when the load runs: exit 2, FILE:LINE, the earlier
# results and the system kept
sed '/^[-0-9]/s/^\(\([^ ]* \)\{4\}\)[01] /\12 /' good.state > colour.state
line=$(grep -n '^[-0-9][^ ]* [^ ]* [^ ]* [^ ]* 2 ' colour.state | head -n 1 | cut -d: -f1)
printf '%b' "${H}disks 5 5\nplace\nsave before.state\nload colour.state\n" > s5.mote
"$MOTE" run s5.mote > out.txt 2> err.txt
st=$?
[ "$st" -eq 2 ] && grep -q "^s5.mote:5:1: error: colour.state:$line: colour must be in \\[0, 1\\], found 2" err.txt &&
    [ -s before.state ] && ok || bad "s5.mote: status $st: $(cat err.txt)"
head -n 55 good.state > cut.state
printf '%b' "${H}disks 5 5\nplace\nload cut.state\n" > s6.mote
"$MOTE" run s6.mote > out.txt 2> err.txt
grep -q "cut.state:56: file ends early: fewer disk lines than n" err.txt && ok || bad "s6.mote: $(cat err.txt)"
sed 's/^n 10$/n 11/' good.state > count.state
printf '%b' "${H}load count.state\nrun 0.1\n" > s7.mote
"$MOTE" run s7.mote > out.txt 2> err.txt
grep -q "count.state:[0-9]*: placed n_left + n_right must equal n" err.txt && ok || bad "s7.mote: $(cat err.txt)"

# the monitor is followed as it grows (issue 53): m.dat.partial while a run writes it, gone when
# the complete file is there; a run stopped with SIGINT halfway leaves its rows so far in the
# partial file, readable, and the earlier complete file untouched
MBP='model mixing-box\nbox 0 0.4 0 0.2\npartition 0.2 0.01\nslit 0.1 0.04\nradius 0.004\ndisks 30 20\nv_init 1\nplace\n'
printf '%bmonitor dt=0.01 file=mp.dat\nrun 0.1\n' "$MBP" > mp1.mote
"$MOTE" run mp1.mote > out.txt 2> err.txt && [ -s mp.dat ] && [ ! -e mp.dat.partial ] && ok || bad "mp1: $(cat err.txt; ls mp.dat*)"
cp mp.dat mp.before
printf '%bmonitor dt=0.01 file=mp.dat\nrun 50000\n' "$MBP" > mp2.mote
sigint_after_rows mp2.mote mp.dat.partial 5 mp2.out
[ "$sigint_rc" -eq 130 ] && grep -q "^mote: stopped by Ctrl-C (SIGINT)" mp2.out && ok || bad "the run was not stopped at a safe point by SIGINT: $(cat mp2.out)"
cmp -s mp.dat mp.before && ok || bad "the complete mp.dat changed under a run that was stopped"
awk '/^# columns:/ { n = NF - 2 } !/^#/ { rows++; if (NF != n) bad = 1 } END { exit !(n == 21 && rows >= 5 && !bad) }' mp.dat.partial &&
    ok || bad "the stopped run's rows: $(head -c 600 mp.dat.partial)"

# the parameter commands bound to the state's descriptors (mote_cmd_set): each sets the next
# run's value that save writes ("next ..." lines), words by their place, and load gives it back
printf 'model mixing-box\ndisks 20 20\nplace\nradius 0.02\nv_init 3\nloss 0.25\ngravity 2.5\nt_c 0.001\nintegrator timestep\ncollision_rule seed\nsave par.state\nload par.state\nsave par2.state\n' > par.mote
if "$MOTE" run par.mote > par.out 2>&1; then ok; else bad "par.mote: $(tail -2 par.out)"; fi
got=$(grep -E '^next (r|v_init|loss|g|t_c|integrator|collision_rule) ' par.state | tr '\n' ';')
[ "$got" = "next r 0.02;next v_init 3;next loss 0.25;next g 2.5;next t_c 0.001;next integrator timestep;next collision_rule seed;" ] && ok || bad "bound parameters in the state file: $got"
cmp -s par.state par2.state && ok || bad "bound parameters: save, load, save differ"

mote_test_end
