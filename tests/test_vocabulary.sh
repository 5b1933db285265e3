#!/bin/sh
# test_vocabulary.sh BUILD_DIR: one vocabulary (issue 34). The output commands take the same
# key=value options in every model (file=, prefix= or dir=, every= for a count, dt= for
# simulated time), `snapshot file=`, `monitor` and `trajectory` are words of every model that
# has the thing they write, and the short positional forms of the commands that had them still
# work and mean the same. Each script's files are checked to exist and to be what was asked.
NAME=vocabulary
. "$(dirname "$0")/lib.sh"
mote_test_start "$1"

# run NAME TEXT: write the script NAME.mote and run it; its output goes to NAME.out
run() {
    printf '%b' "$2" > "$1.mote"
    if "$MOTE" run "$1.mote" > "$1.out" 2>&1; then ok; else bad "$1: $(tail -3 "$1.out")"; fi
}
# has FILE WHAT: FILE exists and is not empty
has() { [ -s "$1" ] && ok || bad "$2: $1 was not written"; }
# rows FILE: the data rows of a mote data file (lines not starting with #)
rows() { grep -vc '^#' "$1"; }

# hard spheres: snapshot file=, trajectory every= file= (dump's other name), the short forms
run hs 'model hard-spheres\nnew 2 0.3\nsnapshot file=hs1.xyz\ntrajectory every=1 file=hs2.xyz\nstep 2\ndump_stop\nsnapshot hs3.xyz\ndump 1 hs4.xyz\nstep 1\n'
has hs1.xyz "hard spheres: snapshot file="
[ "$(grep -c Lattice hs2.xyz)" = 3 ] && ok || bad "hard spheres: trajectory every=1 over step 2: $(grep -c Lattice hs2.xyz) frames"
cmp -s hs1.xyz hs3.xyz && bad "hard spheres: snapshots before and after step 2 are the same" || ok
[ "$(grep -c Lattice hs4.xyz)" = 2 ] && ok || bad "hard spheres: dump 1 FILE over step 1: $(grep -c Lattice hs4.xyz) frames"

# hard spheres' trajectory by time: frames at t0 + j dt exactly, the run the same bit for bit
run hsdt 'model hard-spheres\nseed 5\nnew 2 0.35\ntrajectory dt=0.05 file=hsdt.xyz\nstep 10\nsave hsdt.state\n'
run hsnodt 'model hard-spheres\nseed 5\nnew 2 0.35\nstep 10\nsave hsnodt.state\n'
cmp -s hsdt.state hsnodt.state && ok || bad "hard spheres: trajectory dt= changed the run"
T=$(grep -o 't=[0-9.]*' hsdt.out | tail -1 | cut -d= -f2)
awk -v T="$T" '/Time=/ { match($0, /Time=[^ ]*/); t = substr($0, RSTART + 5, RLENGTH - 5); if (t + 0 != 0.05 * n) bad = 1; n++ }
    END { exit !(!bad && n == int(T / 0.05) + 1 && n > 3) }' hsdt.xyz && ok || bad "hard spheres: trajectory dt=0.05 over t=$T: $(grep -c Lattice hsdt.xyz) frames, times $(grep -o 'Time=[^ ]*' hsdt.xyz | head -3 | tr '\n' ' ')"
expect 1 "hsb.mote:2:1: error: trajectory: give every=K (collisions per particle) or dt=T (time), one of them" hsb.mote 'new 2 0.3\ntrajectory file=a.xyz\n'

# hard spheres' monitor: a row now and at t0 + j dt, the run the same bit for bit; over the
# interval of `pressure K` a row every K gives the pressure command's own estimates (the same
# sums: P_virial in a periodic box, P_left and P_right in a slit)
run hsm 'model hard-spheres\nseed 5\nnew 2 0.35\nmonitor dt=0.05 file=hsm.dat\nstep 10\nsave hsm.state\n'
cmp -s hsm.state hsnodt.state && ok || bad "hard spheres: monitor dt= changed the run"
awk -v T="$T" '!/^#/ { if ($1 + 0 != 0.05 * n || NF != 7) bad = 1; n++ } END { exit !(!bad && n == int(T / 0.05) + 1) }' hsm.dat &&
    grep -q '^# columns: t collisions wall_collisions kT P_virial P_left P_right$' hsm.dat && ok || bad "hard spheres: monitor dt=0.05 over t=$T: $(grep -vc '^#' hsm.dat) rows"
run hsp 'model hard-spheres\nseed 5\nbulk 108 0.3\nstep 5\nmonitor every=10 file=hsp.dat\npressure 10 hsp_p.dat\nplot hsp.dat hsp.png\n'
has hsp.png "hard spheres: plot of a monitor"
p=$(sed -n 's/^# P_virial = \([^ ]*\) .*/\1/p' hsp_p.dat)
tail -1 hsp.dat | awk -v p="$p" '{ exit !(p != "" && ($5 - p) ^ 2 <= (1e-11 * p) ^ 2) }' && ok || bad "hard spheres: monitor P_virial $(tail -1 hsp.dat | cut -d' ' -f5) vs pressure's $p"
run hss 'model hard-spheres\nseed 5\nnew 3 0.35\nstep 5\nmonitor 20 hss.dat\npressure 20 hss_p.dat\n'
pl=$(sed -n 's/^# P_left = \([^ ]*\) .*/\1/p' hss_p.dat)
pr=$(sed -n 's/^# P_right = \([^ ]*\) .*/\1/p' hss_p.dat)
tail -1 hss.dat | awk -v l="$pl" -v r="$pr" '{ exit !(l != "" && r != "" && ($6 - l) ^ 2 <= (1e-11 * l) ^ 2 && ($7 - r) ^ 2 <= (1e-11 * r) ^ 2) }' &&
    ok || bad "hard spheres: monitor P_left P_right $(tail -1 hss.dat | cut -d' ' -f6,7) vs pressure's $pl $pr"

# the vocabulary table of `mote help --markdown` is made from the command tables: a row per
# shared word, a column per model, the earlier words named as aliases
"$MOTE" help --markdown > ref.md
grep -q '^| the configuration (now, or on a schedule) | `snapshot every= dt= file= prefix= format=` | `snapshot every= dt= file= prefix= format=` | `snapshot every= dt= file= prefix= format=` | — | `snapshot every= dt= file= prefix= format=` |$' ref.md && ok || bad "table: $(grep '^| the configuration' ref.md)"
grep -q '^| particle paths (a growing file) | `trajectory every= dt= file= format=` | `trajectory every= dt= file= format=` | `trajectory every= dt= file= format=` | — | `trajectory every= dt= file= format=` |$' ref.md && ok || bad "table: $(grep '^| particle paths' ref.md)"
grep -q '^| the run.s quantities over time | `monitor every= dt= file= format=` | `monitor every= dt= file= format=` | `monitor every= dt= file= format=` | `monitor dt= file= format=` | `monitor every= dt= file= format=` |$' ref.md && ok || bad "table: $(grep '^| the run.s quantities' ref.md)"
grep -q '^| the exact state on a schedule | `checkpoint every= file=` | `checkpoint every= file=` | `checkpoint every= file=` | — | `checkpoint every= file=` |$' ref.md && ok || bad "table: $(grep '^| the exact state on' ref.md)"
grep -q "^Other names kept as aliases (.mote help. marks them): .dump. (hard-spheres's .trajectory.), .record. (mixing-box's .monitor.), .snapshots. (separator's .snapshot.), .balance. (separator's .monitor.).$" ref.md && ok || bad "aliases: $(grep '^Other names' ref.md)"

# the mixing box: monitor dt= file= (record's other name), snapshot file=, frames dt= prefix=,
# density_y with its options; and record's short form gives the same rows
MB='model mixing-box\nbox 0 2 0 1\npartition 1 0.02\nslit 0.5 0.1\nradius 0.01\ndisks 40 40\nv_init 1\nplace\n'
run mb "${MB}monitor dt=0.25 file=mb1.dat\nsnapshot file=mb2.png\nframes dt=0.5 prefix=mbf\ndensity_y dt=0.25 bins=8 file=mb3.dat\nrun 1\n"
run mb_short "${MB}record 0.25 mb1.dat\nsnapshot mb2.png\nframes 0.5 mbs\ndensity_y 0.25 8 mb3s.dat\nrun 1\n"
[ "$(rows mb1.dat)" = 5 ] && ok || bad "mixing box: monitor dt=0.25 over run 1: $(rows mb1.dat) rows, not 5"
has mb2.png "mixing box: snapshot file="
[ -s mbf_000002.png ] && [ ! -e mbf_000003.png ] && ok || bad "mixing box: frames dt=0.5 over run 1: $(ls mbf_* | wc -l) frames, not 3"
[ "$(rows mb3.dat)" = 8 ] && ok || bad "mixing box: density_y bins=8: $(rows mb3.dat) rows"
cmp -s mb3.dat mb3s.dat && bad "mixing box: the two density files share a header, they cannot be equal" || ok
grep -v '^#' mb3.dat > a.txt; grep -v '^#' mb3s.dat > b.txt
cmp -s a.txt b.txt && ok || bad "mixing box: density_y's key and short forms differ"

# every=K and dt=T in every model that has a count and a clock (issue 53): the mixing box's
# monitor and frames by disk-disk collisions (a row at each multiple, the event engine stops
# there exactly), the run the same bit for bit with and without them
run mbe "${MB}monitor every=100 file=mbe.dat\nframes every=250 prefix=mbe\nrun_collisions 1000 100\nsave mbe.state\n"
run mbe0 "${MB}run_collisions 1000 100\nsave mbe0.state\n"
awk '!/^#/ { if ($20 != 100 * n) bad = 1; n++ } END { exit !(!bad && n == 11) }' mbe.dat && ok || bad "mixing box: monitor every=100 over 1000 collisions: collisions $(grep -v '^#' mbe.dat | awk '{printf "%s ", $20}')"
grep -q '^# every = 100 disk-disk collisions$' mbe.dat && ok || bad "mixing box: monitor every= header: $(grep '^# every\|^# DT' mbe.dat)"
[ -s mbe_000004.png ] && [ ! -e mbe_000005.png ] && ok || bad "mixing box: frames every=250 over 1000 collisions: $(ls mbe_* | tr '\n' ' ')"
cmp -s mbe.state mbe0.state && ok || bad "mixing box: monitor/frames every= changed the run"
# the timestep integrator goes several collisions at a time: a row at the step that passes
# each multiple of 100 (never two for one multiple, never one without)
run mbt "${MB}integrator timestep\nmonitor every=100 file=mbt.dat\nrun_collisions 1000 100\n"
awk '!/^#/ { c = $20 + 0; if (n && (int(c / 100) <= int(last / 100) || c - 100 * int(c / 100) >= 100)) bad = 1; last = c; n++ } END { exit !(!bad && n >= 10) }' mbt.dat && ok || bad "mixing box (timestep): monitor every=100: collisions $(grep -v '^#' mbt.dat | awk '{printf "%s ", $20}')"
expect 1 "mbb.mote:9:1: error: monitor: give every=K (a count) or dt=T (a time)" mbb.mote "${MB}monitor file=a.dat\n"
expect 1 "mbc.mote:9:19: error: frames: give every=K or dt=T, not both" mbc.mote "${MB}frames every=5 dt=0.1 prefix=a\n"

# snapshots on a schedule in the hard spheres and the mixing box: one now, then each its own
# numbered file, the run the same bit for bit; the same prefix again continues the numbering
run hss5 'model hard-spheres\nseed 5\nnew 2 0.35\nsnapshot every=2 prefix=hss5/a\nstep 6\nsnapshot dt=0.5 prefix=hss5/a\nstep 2\nsave hss5.state\n'
run hss6 'model hard-spheres\nseed 5\nnew 2 0.35\nstep 6\nstep 2\nsave hss6.state\n'
[ "$(cat hss5/a_00000[0-3].xyz | grep -o 'collisions=[0-9]*' | tr '\n' ' ')" = "collisions=0 collisions=64 collisions=128 collisions=192 " ] && [ -s hss5/a_000004.xyz ] && ok || bad "hard spheres: snapshot every=2 (64 collisions) over 192, then dt=: $(ls hss5 | tr '\n' ' ') $(cat hss5/*.xyz | grep -o 'collisions=[0-9]*' | tr '\n' ' ')"
cmp -s hss5.state hss6.state && ok || bad "hard spheres: snapshot every=/dt= changed the run"
run mbs5 "${MB}snapshot every=200 prefix=mbs5/a\nrun_collisions 1000 100\nsnapshot_stop\nsnapshot dt=0.25 prefix=mbs5/b\nrun 1\nsave mbs5.state\n"
run mbs6 "${MB}run_collisions 1000 100\nrun 1\nsave mbs6.state\n"
[ "$(ls mbs5 | grep -c '^a_')" = 6 ] && [ "$(ls mbs5 | grep -c '^b_')" = 5 ] && ok || bad "mixing box: snapshot every=200 over 1000 collisions, dt=0.25 over 1 s: $(ls mbs5 | tr '\n' ' ')"
cmp -s mbs5.state mbs6.state && ok || bad "mixing box: snapshot every=/dt= changed the run"
expect 1 "mbs7.mote:9:1: error: snapshot: a series needs prefix=P (files P_000000.xyz, ...)" mbs7.mote "${MB}snapshot every=5\n"

# the hard spheres' frames: a picture now and on the schedule (the cut at z = Lz/2, coloured
# by local order), the run the same bit for bit
run hsf 'model hard-spheres\nseed 5\nnew 2 0.35\nframes every=2 prefix=hsf/a\nstep 6\nframes_stop\nstep 2\nsave hsf.state\n'
[ "$(ls hsf | tr '\n' ' ')" = "a_000000.png a_000001.png a_000002.png a_000003.png " ] && ok || bad "hard spheres: frames every=2 over step 6: $(ls hsf | tr '\n' ' ')"
head -c 8 hsf/a_000000.png | od -An -c | grep -q 'P   N   G' && ok || bad "hard spheres: frames: not a PNG"
cmp -s hsf.state hss6.state && ok || bad "hard spheres: frames changed the run"

# trajectory in the mixing box and the separator (a growing XYZ file: a frame at each time, the
# run the same bit for bit)
run mbtr "${MB}trajectory every=250 file=mbtr.xyz\nrun_collisions 1000 100\ntrajectory_stop\nrun 1\nsave mbtr.state\n"
[ "$(grep -c Lattice mbtr.xyz)" = 5 ] && ok || bad "mixing box: trajectory every=250 over 1000 collisions: $(grep -c Lattice mbtr.xyz) frames, not 5"
cmp -s mbtr.state mbs6.state && ok || bad "mixing box: trajectory changed the run"
run septr "${SEP_DILUTE}trajectory dt=0.1 file=septr.xyz\nrun 0.3\n"
# (the frames' times are the steps' own, exact: 0.1 to within the steps' rounding)
grep -o 'Time=[^ ]*' septr.xyz | awk -F= '{ t[NR] = $2 + 0 } END { for (k = 1; k <= 4; k++) { d = t[k] - 0.1 * (k - 1); if (d < 0) d = -d; if (d > 1e-12 || NR != 4) exit 1 } }' && ok || bad "separator: trajectory dt=0.1 over run 0.3: $(grep -o 'Time=[^ ]*' septr.xyz | tr '\n' ' ')"

# the separator's monitor, snapshots and frames every K steps: the first at the run's start,
# then at each multiple (steps of 1e-3 s: t = steps / 1000), the run the same bit for bit
SEPT="${SEP_DILUTE}"
run sepe "${SEPT}monitor file=sepe.dat every=50\nsnapshot every=100 prefix=sepe_s/a\nframes every=150 prefix=sepe_f/a movie=off\nrun 0.3\nsave sepe.state\n"
run sepe0 "${SEPT}run 0.3\nsave sepe0.state\n"
awk '!/^#/ { if (($1 - 0.05 * n) ^ 2 > 1e-20) bad = 1; n++ } END { exit !(!bad && n == 7) }' sepe.dat && ok || bad "separator: monitor every=50 over 300 steps: t $(grep -v '^#' sepe.dat | awk '{printf "%s ", $1}')"
[ "$(ls sepe_s | wc -l)" = 4 ] && [ "$(ls sepe_f | wc -l)" = 3 ] && ok || bad "separator: snapshot every=100, frames every=150 over 300 steps: $(ls sepe_s sepe_f | tr '\n' ' ')"
cmp -s sepe.state sepe0.state && ok || bad "separator: outputs every= changed the run"

# nbody's snapshots and frames every T of time: the bodies at that exact time (the Taylor
# step's dense output), numbered in order; the run the same bit for bit
run nbt 'model nbody gravity\ngenerate ring nb=6\nsnapshot dt=0.25 prefix=nbt_s/a\nframes dt=0.5 prefix=nbt_f/a\nintegrate to=1\nintegrate to=1.5\nsave nbt.state\n'
run nbt0 'model nbody gravity\ngenerate ring nb=6\nintegrate to=1\nintegrate to=1.5\nsave nbt0.state\n'
[ "$(cat nbt_s/a_00000[0-5].snap | sed -n 's/^# T = //p' | tr '\n' ' ')" = "0.25 0.5 0.75 1 1.25 1.5 " ] && [ ! -e nbt_s/a_000006.snap ] && ok || bad "nbody: snapshot dt=0.25 to 1.5: $(ls nbt_s | tr '\n' ' '), T $(cat nbt_s/*.snap | sed -n 's/^# T = //p' | tr '\n' ' ')"
[ -s nbt_f/a_000003.png ] && [ ! -e nbt_f/a_000004.png ] && ok || bad "nbody: frames dt=0.5 to 1.5 (one now and three): $(ls nbt_f | tr '\n' ' ')"
cmp -s nbt.state nbt0.state && ok || bad "nbody: snapshot/frames dt= changed the run"
expect 1 "nbb.mote:3:1: error: snapshot: give file=FILE (one now) or every=K (one every K steps of integrate) or dt=T (one every T of time), not both" \
    nbb.mote 'model nbody gravity\ngenerate ring nb=6\nsnapshot file=a.snap dt=2\n'

# nbody: snapshot file= (one now) beside snapshot every=; monitor, trajectory
run nb 'model nbody gravity\ngenerate ring nb=6\nsnapshot file=nb1.snap\nsnapshot every=5 prefix=nbs_\nmonitor every=5 file=nb2.dat\ntrajectory every=5 file=nb3.dat\nintegrate steps=10\n'
has nb1.snap "nbody: snapshot file="
has nbs_0000000010.snap "nbody: snapshot every=5"
[ "$(rows nb2.dat)" = 3 ] && ok || bad "nbody: monitor every=5 over 10 steps: $(rows nb2.dat) rows"
[ "$(rows nb3.dat)" = 3 ] && ok || bad "nbody: trajectory every=5 over 10 steps: $(rows nb3.dat) rows"
expect 1 "nb_bad.mote:3:1: error: snapshot: give file=FILE (one now) or every=K (one every K steps of integrate) or dt=T (one every T of time), not both" \
    nb_bad.mote 'model nbody gravity\ngenerate ring nb=6\nsnapshot file=a.snap every=2\n'

# the separator: monitor file= dt= (balance's other name), snapshot dir= dt= (snapshots'),
# frames dir= dt=, tromp file=; and the short forms
mkdir sn fr sn2
run sep "${SEP_DILUTE}monitor file=sep1.dat dt=0.1\nsnapshot dir=sn dt=0.1\nframes dir=fr dt=0.2 movie=off\nrun 0.3\ntromp file=sep2.dat\n"
[ "$(rows sep1.dat)" -ge 3 ] && ok || bad "separator: monitor dt=0.1 over run 0.3: $(rows sep1.dat) rows"
[ "$(ls sn | wc -l)" -ge 3 ] && ok || bad "separator: snapshot dir=sn dt=0.1: $(ls sn | wc -l) files"
[ "$(ls fr | grep -c png)" -ge 2 ] && ok || bad "separator: frames dir=fr dt=0.2: $(ls fr | wc -l) files"
has sep2.dat "separator: tromp file="
run sep_short "${SEP_DILUTE}balance sep3.dat 0.1\nsnapshots sn2 0.1\nrun 0.3\ntromp sep4.dat\n"
grep -v '^#' sep1.dat > a.txt; grep -v '^#' sep3.dat > b.txt
cmp -s a.txt b.txt && ok || bad "separator: balance's short form and monitor differ"
[ "$(ls sn2 | wc -l)" = "$(ls sn | wc -l)" ] && ok || bad "separator: snapshots DIR DT wrote $(ls sn2 | wc -l) files, snapshot dir= $(ls sn | wc -l)"

# numbered files are named alike in every model (PREFIX_000000.png on; no '_' is added after a
# prefix ending in '_' or '/'), the same prefix or folder again continues the numbering, and
# check reports a series that would start again over earlier files, or a file among its names
run nbf 'model nbody gravity\ngenerate ring nb=6\nframes every=5 prefix=nbf\nintegrate steps=10\nframes every=10 prefix=nbf\nintegrate steps=10\n'
[ -s nbf_000000.png ] && [ -s nbf_000004.png ] && [ ! -e nbf_000005.png ] && ok || bad "nbody: frames prefix=nbf twice: $(ls nbf_* | tr '\n' ' ')"
mkdir nbg
run nbg 'model nbody gravity\ngenerate ring nb=6\nframes every=10 prefix=nbg/\nframes every=10 prefix=nbg_\n'
[ -s nbg/000000.png ] && [ -s nbg_000000.png ] && ok || bad "nbody: frames prefix=nbg/ and nbg_: $(ls nbg nbg_* | tr '\n' ' ')"
mkdir frc
run sepf "${SEP_DILUTE}frames dir=frc dt=0.1 movie=off\nrun 0.1\nframes dir=frc dt=0.1 movie=off\nrun 0.1\n"
[ -s frc/frame_000003.png ] && [ ! -e frc/frame_000004.png ] && ok || bad "separator: frames dir=frc twice: $(ls frc | tr '\n' ' ')"
NB='model nbody gravity\ngenerate ring nb=6\n'
expect 0 "w1.mote:7:1: warning: frames: its numbered files start again from 0 and overwrite those of line 3 (a_*.png)" \
    w1.mote "${NB}frames every=5 prefix=a\nintegrate steps=10\nframes every=5 prefix=b\nintegrate steps=10\nframes every=5 prefix=a\n" check
expect 0 "w2.mote:4:1: warning: snapshot: 'a_000003.png' is also one of the numbered files (frames) of line 3" \
    w2.mote "${NB}frames every=5 prefix=a\nsnapshot file=a_000003.png\n" check
expect 0 "w3.mote:4:1: warning: snapshot: 'sn_0000000100.snap', written by line 3, is also one of its numbered files" \
    w3.mote "${NB}write snapshot file=sn_0000000100.snap\nsnapshot every=5 prefix=sn\n" check
expect 0 "" w4.mote "${NB}snapshot every=5 prefix=sn\nsnapshot every=5 prefix=so\nsnapshot every=5 prefix=sn\nframes every=5 prefix=sn\n" check
expect 0 "w5.mote:6:1: warning: frames: its numbered files start again from 0 and overwrite those of line 2 (fr/frame_*.png)" \
    w5.mote 'model separator\nframes dir=fr dt=0.1\nsnapshot dir=fr dt=0.1\nframes dir=fr dt=0.2\nframes dir=g dt=0.1\nframes dir=fr dt=0.1\n' check
expect 0 "w6.mote:10:1: warning: snapshot: 'f_000002.png' is also one of the numbered files (frames) of line 9" \
    w6.mote "${MB}frames 0.1 f\nsnapshot f_000002.png\n" check
# prefix= makes its folder as dir= does (issue 52), when the folder's parent exists
expect 0 "" w7a.mote "${NB}frames prefix=made/f every=1\n" check
expect 1 "w7.mote:3:15: error: frames: the directory that would hold 'nodir/sub' does not exist" \
    w7.mote "${NB}frames prefix=nodir/sub/f every=1\n" check

# the stops (one row made by the core, MOTE_CMD_STOP): every output a model starts on a
# schedule has WORD_stop; after it a later run adds nothing to what was written (the files are
# those of the same script ended at the stop), and the run itself is the same bit for bit
data() { grep -v '^#' "$1"; }
# same_rows A B WHAT: the same data rows in A and B (their first five columns: not the timings)
same_rows() { [ "$(data "$1" | cut -d' ' -f1-5)" = "$(data "$2" | cut -d' ' -f1-5)" ] && [ -n "$(data "$1")" ] && ok || bad "$3: $1 $(data "$1" | wc -l) rows, $2 $(data "$2" | wc -l)"; }
count() { ls "$1" 2>/dev/null | wc -l; }
NBO='monitor every=5 file=OUT_m.dat\ntrajectory every=5 file=OUT_t.dat\nframes every=5 prefix=OUT_f/a\nsnapshot every=5 prefix=OUT_s/a\ncheckpoint every=5 file=OUT.ck\nintegrate steps=10\n'
NBS='monitor_stop\ntrajectory_stop\nframes_stop\nsnapshot_stop\ncheckpoint_stop\n'
run nbst "${NB}$(printf "%s" "$NBO" | sed s/OUT/nbst/g)${NBS}integrate steps=10\nsave nbst.state\n"
run nbst0 "${NB}$(printf "%s" "$NBO" | sed s/OUT/nbst0/g)${NBS}"
run nbst1 "${NB}integrate steps=20\nsave nbst1.state\n"
same_rows nbst_m.dat nbst0_m.dat "nbody: monitor_stop"
same_rows nbst_t.dat nbst0_t.dat "nbody: trajectory_stop"
[ "$(count nbst_f)" = "$(count nbst0_f)" ] && [ "$(count nbst_s)" = "$(count nbst0_s)" ] && [ "$(count nbst_s)" -ge 2 ] && ok || bad "nbody: frames_stop, snapshot_stop: $(count nbst_f) frames, $(count nbst_s) snapshots; $(count nbst0_f) and $(count nbst0_s) without the later run"
cmp -s nbst.ck nbst0.ck && ok || bad "nbody: checkpoint_stop: the checkpoint changed after it"
cmp -s nbst.state nbst1.state && ok || bad "nbody: the run with stopped outputs is not the same"
SPO='monitor file=OUT_m.dat every=50\nsnapshot every=100 prefix=OUT_s/a\nframes every=150 prefix=OUT_f/a movie=off\ntrajectory every=100 file=OUT_t.xyz\nrun 0.2\n'
SPS='monitor_stop\nsnapshot_stop\nframes_stop\ntrajectory_stop\n'
run sepst "${SEP_DILUTE}$(printf "%s" "$SPO" | sed s/OUT/sepst/g)${SPS}run 0.1\nsave sepst.state\n"
run sepst0 "${SEP_DILUTE}$(printf "%s" "$SPO" | sed s/OUT/sepst0/g)${SPS}"
run sepst1 "${SEP_DILUTE}run 0.2\nrun 0.1\nsave sepst1.state\n"
same_rows sepst_m.dat sepst0_m.dat "separator: monitor_stop"
cmp -s sepst_t.xyz sepst0_t.xyz && ok || bad "separator: trajectory_stop: frames added after it"
[ "$(count sepst_f)" = "$(count sepst0_f)" ] && [ "$(count sepst_s)" = "$(count sepst0_s)" ] && [ "$(count sepst_s)" -ge 2 ] && ok || bad "separator: frames_stop, snapshot_stop: $(count sepst_f) and $(count sepst_s) files, $(count sepst0_f) and $(count sepst0_s) without the later run"
cmp -s sepst.state sepst1.state && ok || bad "separator: the run with stopped outputs is not the same"
run mbst "${MB}monitor every=100 file=mbst_m.dat\nrun_collisions 1000 100\nmonitor_stop\nrun_collisions 500 100\nsave mbst.state\n"
run mbst0 "${MB}monitor every=100 file=mbst0_m.dat\nrun_collisions 1000 100\n"
same_rows mbst_m.dat mbst0_m.dat "mixing box: monitor_stop"
CHS='model charging faithful\nbody sphere radius=1\nrun particles=2e4\nmonitor dt=2.5e-5 file=OUT.csv\nevolve time=1e-4\n'
run chst "$(printf "%s" "$CHS" | sed s/OUT/chst/)monitor_stop\nevolve time=2e-4\n"
run chst0 "$(printf "%s" "$CHS" | sed s/OUT/chst0/)"
cmp -s chst.csv chst0.csv && ok || bad "charging: monitor_stop: a later evolve wrote to the monitor's file"

# checkpoint (the exact state on a schedule) in hard spheres: it only reads the run (the same
# bits with and without); the file at a count is what `save` writes after a command that ends
# there; `load` of it and the rest go on bit for bit as that split run
HSC='model hard-spheres\nseed 5\nnew 2 0.35\n'
run hsc "${HSC}checkpoint every=2 file=hsc.state\nstep 6\nsave hsc6.state\ncheckpoint_stop\nstep 2\n"
run hsc0 "${HSC}step 6\nsave hsc0.state\n"
run hsc1 "${HSC}step 4\nsave hsc1.state\nstep 2\nsave hsc1b.state\n"
run hsc2 "${HSC}checkpoint every=2 file=hsc2.state\nstep 5\n"
run hsc3 'model hard-spheres\nload hsc2.state\nstep 2\nsave hsc3.state\n'
cmp -s hsc6.state hsc0.state && ok || bad "hard spheres: checkpoint changed the run"
cmp -s hsc.state hsc0.state && ok || bad "hard spheres: the checkpoint at 6 is not save's state at 6 / checkpoint_stop"
cmp -s hsc2.state hsc1.state && ok || bad "hard spheres: the checkpoint at 4 (mid-run) is not save's state after step 4"
cmp -s hsc3.state hsc1b.state && ok || bad "hard spheres: load of a checkpoint does not continue as the split run"
# checkpoint in the separator: only reads the run (the same bits with and without); the state
# at a step, loaded, goes on step for step as the run that wrote it (its checkpoint K steps on
# is the uninterrupted run's, bit for bit: the state at a loop's stop is complete)
run sepc "${SEP_DILUTE}checkpoint every=100 file=sepc.state\nrun 0.25\nsave sepc_end.state\n"
run sepc0 "${SEP_DILUTE}run 0.25\nsave sepc0_end.state\n"
run sepc1 "${SEP_DILUTE}checkpoint every=100 file=sepc1.state\nrun 0.15\n"
run sepc2 'model separator\nload sepc1.state\ncheckpoint every=100 file=sepc2.state\nrun 0.15\ncheckpoint_stop\nrun 0.1\n'
cmp -s sepc_end.state sepc0_end.state && ok || bad "separator: checkpoint changed the run"
cmp -s sepc2.state sepc.state && grep -q '^real t 0.2000' sepc2.state && ok || bad "separator: load of a checkpoint did not go on step for step ($(grep '^real t ' sepc2.state sepc.state | tr '\n' ' '))"

# checkpoint in the mixing box (both integrators): only reads the run; the file at a count is
# save's after a run ending there; load of it goes on as the run split there
for integ in event timestep; do
    MBC="${MB}integrator ${integ}\n"
    run mbc_$integ "${MBC}checkpoint every=200 file=mbc_$integ.state\nrun_collisions 1000 100\nsave mbc_${integ}_a.state\ncheckpoint_stop\nrun_collisions 200 100\n"
    run mbc0_$integ "${MBC}run_collisions 1000 100\nsave mbc0_$integ.state\n"
    run mbc1_$integ "${MBC}run_collisions 400 100\nsave mbc1_$integ.state\nrun_collisions 200 100\nsave mbc1b_$integ.state\n"
    run mbc2_$integ "${MBC}checkpoint every=200 file=mbc2_$integ.state\nrun_collisions 500 100\n"
    run mbc3_$integ "model mixing-box\nload mbc2_$integ.state\nrun_collisions 200 100\nsave mbc3_$integ.state\n"
    cmp -s mbc_${integ}_a.state mbc0_$integ.state && ok || bad "mixing box ($integ): checkpoint changed the run"
    cmp -s mbc_$integ.state mbc0_$integ.state && ok || bad "mixing box ($integ): the checkpoint at 1000 is not save's / checkpoint_stop"
    cmp -s mbc2_$integ.state mbc1_$integ.state && ok || bad "mixing box ($integ): the checkpoint at 400 (mid-run) is not save's after 400"
    cmp -s mbc3_$integ.state mbc1b_$integ.state && ok || bad "mixing box ($integ): load of a checkpoint does not continue as the split run"
done

# format=table|csv|jsonl for every model's monitor (the core's rows: the partial file is the
# table, FILE is written in the form asked; a .csv name is CSV): each JSON line an object with
# the columns of the table file, the same values; CSV with the table's header row
jsonl_ok() { # FILE TABLE WHAT: FILE's objects hold TABLE's rows (the table: the same run)
    /usr/bin/python3 - "$1" "$2" <<'PY' && ok || bad "$3: $1 is not the JSON lines of $2"
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
table = [l.split() for l in open(sys.argv[2]) if not l.startswith('#')]
cols = [l.split()[2:] for l in open(sys.argv[2]) if l.startswith('# columns:')][0]
def same(v, w):
    return v is None and w in ('nan', 'inf', '-inf') or v is not None and float(w) == v
assert len(rows) == len(table) > 1, (len(rows), len(table))
for o, t in zip(rows, table):
    assert list(o)[1:] == cols and all(same(o[c], w) for c, w in zip(cols, t)), (o, t)
PY
}
run fmths 'model hard-spheres\nseed 5\nnew 2 0.35\nmonitor dt=0.5 file=fmt_hs.dat\nstep 4\n'
run fmths2 'model hard-spheres\nseed 5\nnew 2 0.35\nmonitor dt=0.5 file=fmt_hs.json format=jsonl\nstep 4\n'
jsonl_ok fmt_hs.json fmt_hs.dat "hard spheres: monitor format=jsonl"
run fmtmb "${MB}monitor dt=0.25 file=fmt_mb.dat\nrun 1\n"
run fmtmb2 "${MB}monitor dt=0.25 file=fmt_mb.json format=jsonl\nrun 1\nmonitor dt=0.25 file=fmt_mb2.txt format=csv\nrun 0.5\n"
jsonl_ok fmt_mb.json fmt_mb.dat "mixing box: monitor format=jsonl"
head -1 fmt_mb2.txt | grep -q '^t,nL0,nL1,' && [ "$(wc -l < fmt_mb2.txt)" -eq 4 ] && ok || bad "mixing box: monitor format=csv: $(head -2 fmt_mb2.txt)"
run fmtsep "${SEP_DILUTE}monitor file=fmt_sep.dat dt=0.1\nrun 0.2\n"
run fmtsep2 "${SEP_DILUTE}monitor file=fmt_sep.json dt=0.1 format=jsonl\nrun 0.2\n"
jsonl_ok fmt_sep.json fmt_sep.dat "separator: monitor format=jsonl"
CHF='model charging faithful\nbody sphere radius=1\nrun particles=2e4\n'
run fmtch "${CHF}monitor dt=2.5e-5 file=fmt_ch.dat\nevolve time=1e-4\n"
run fmtch2 "${CHF}monitor dt=2.5e-5 file=fmt_ch.json format=jsonl\nevolve time=1e-4\n"
jsonl_ok fmt_ch.json fmt_ch.dat "charging: monitor format=jsonl"

# `picture FILE.png`, common to every model that draws its state: the same picture as the
# model's own (hard spheres' frames, the mixing box's snapshot FILE.png), in the size it has
png_wh() { /usr/bin/python3 -c 'import sys; d = open(sys.argv[1], "rb").read(24); print(int.from_bytes(d[16:20], "big"), int.from_bytes(d[20:24], "big")) if d[:8] == b"\x89PNG\r\n\x1a\n" else print("not-png")' "$1"; }
run pichs 'model hard-spheres\nseed 5\nnew 2 0.35\npicture pic_hs.png\nframes every=1 prefix=pf\n'
cmp -s pic_hs.png pf_000000.png && ok || bad "hard spheres: picture is not the picture of frames"
run picmb "${MB}picture pic_mb.png\nsnapshot pic_mb2.png\n"
cmp -s pic_mb.png pic_mb2.png && ok || bad "mixing box: picture is not snapshot FILE.png"
run picnb 'model nbody\nbody mass=1\nbody mass=1e-3 x=1 vy=1\npicture pic_nb.png\n'
[ "$(png_wh pic_nb.png)" = "1024 768" ] && ok || bad "nbody: picture $(png_wh pic_nb.png)"
run picsep "${SEP_DILUTE}run 0.05\npicture pic_sep.png\n"
[ "$(png_wh pic_sep.png | cut -d" " -f2)" -ge 900 ] && ok || bad "separator: picture $(png_wh pic_sep.png)"
grep -q "picture: wrote pic_sep.png" picsep.out && ok || bad "separator: picture printed $(tail -1 picsep.out)"
expect 1 "picch.mote:3:1: error: picture: the charging model draws no picture of its state (its files and \`plot\` do)" picch.mote 'model charging\nbody sphere radius=1\npicture c.png\n'
expect 1 "picext.mote:3:9: error: picture: FILE must end in .png, found 'p.jpg'" picext.mote 'model hard-spheres\nnew 2 0.3\npicture p.jpg\n'
expect 2 "picnone.mote:2:1: error: picture: there are no bodies yet" picnone.mote 'model nbody\npicture p.png\n'

mote_test_end
