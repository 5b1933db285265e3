#!/bin/sh
# test_separator.sh: the separator model through the `mote` program: the dilute cut size (spec
# 4 V2) from a script with its Tromp table, and bad input: each a located error before anything
# runs, nothing written.
# Usage: sh tests/test_separator.sh [BUILD_DIR]   (default: build)
NAME=separator
. "$(dirname "$0")/lib.sh"
mote_test_start "$1"

S='model separator\n'
printf '%bchannel 0.05 1\ngas 1.0\ncoupling off\ncollisions off\nspecies quartz 2500\nsize quartz loguniform min=75e-6 max=300e-6 basis=number\nfeed z=0.5\nclasses 25 min=75e-6 max=316.2277660e-6\ntimestep 1e-3\ninsert quartz 4000\nrun 30\ntromp tromp.dat\n' "$S" > v2.mote
"$MOTE" run v2.mote > out.txt 2> err.txt && cp tromp.dat t1.dat && ok || bad "v2.mote failed: $(cat err.txt)"
grep -q '^t=30 steps=30000 dt=0.001 N=[0-9]* fed=4000 fines=[0-9]* coarse=[0-9]* lost=0 backlog=0 d50=' out.txt && ok || bad "status: $(grep '^t=' out.txt)"
awk '/^# d50_m = / { d = $4 } /^# kappa = / { k = $4 } /^# d0_star_m quartz = / { s = $5 }
     END { r = d / 151.84e-6 - 1; exit !(r * r <= 0.0004 && k >= 0.9441 && k <= 1 && s > 151.83e-6 && s < 151.85e-6) }' tromp.dat && ok || bad "tromp: $(grep '^#' tromp.dat)"
[ "$(grep -vc '^#' tromp.dat)" -eq 25 ] && ok || bad "tromp rows: $(grep -vc '^#' tromp.dat)"
# the same script and seed give the same file
"$MOTE" run v2.mote > /dev/null 2>&1 && cmp -s t1.dat tromp.dat && ok || bad "two runs differ"
# DEM: 300 glass beads settle in a closed box without gas flow; none lost, the overlap within
# twice delta_f, the status reports the contact fields
printf '%bchannel 0.02 0.06\nends closed closed\ngas 0\nspecies glass 2500\nsize glass mono d=1e-3\nfeed z=0.03 hf=0.05\ninsert glass 300\nrun 0.005\n' "$S" > dem.mote
"$MOTE" run dem.mote > out.txt 2> err.txt && ok || bad "dem.mote failed: $(cat err.txt)"
grep -q '^t=0.005 steps=[0-9]* dt=3.25669e-07 N=300 fed=300 fines=0 coarse=0 lost=0 backlog=0 d50=nan kappa=nan eps_max=[0-9.]* max_overlap=[0-9.e-]* fast_moves=0$' out.txt && ok || bad "dem status: $(cat out.txt)"
awk -F'max_overlap=' '/^t=/ { split($2, a, " "); exit !(a[1] <= 0.1) }' out.txt && ok || bad "dem overlap: $(cat out.txt)"
# V10: save mid-run, load, continue: bit for bit the run that never stopped (a DEM run with two
# species, a gas profile, a grid, dispersion, relaxation, a backlog and profile sums); save,
# load, save gives the same file
printf '0 1.2 1.8e-5\n0.05 1.0 1.9e-5\n' > v10gp.txt
printf '%bseed 7\nchannel 0.01 0.05\ngas 0.3\ngas_profile v10gp.txt\ndispersion 1e-5\nspecies glass 2500\nsize glass loguniform min=0.4e-3 max=0.8e-3\nspecies coal 1400\nsize coal mono d=0.6e-3\nfeed_fraction glass 0.6\nfeed_fraction coal 0.4\nfeed z=0.03 rate=2e-3 stop=0.02\ngrid 0.01 0.001 pattern a=1.2e-3 p=2e-3 offset=0.3e-3\nstiffness overlap=0.05 vimp=1\nrelax 1e-3\naverage_from 0.005\nrun 0.01\nsave s1.state\nrun 0.01\nsave a.state\n' "$S" > v10a.mote
printf '%bload s1.state\nrun 0.01\nsave c.state\n' "$S" > v10c.mote
printf '%bload s1.state\nsave d.state\n' "$S" > v10d.mote
"$MOTE" run v10a.mote > out.txt 2> err.txt && ok || bad "v10a.mote: $(cat err.txt)"
grep -q 'backlog=[1-9]' out.txt && ok || bad "v10a.mote: no backlog: $(cat out.txt)"
"$MOTE" run v10c.mote > /dev/null 2> err.txt && cmp -s a.state c.state && ok || bad "V10: the continued run differs: $(cat err.txt)"
"$MOTE" run v10d.mote > /dev/null 2> err.txt && cmp -s s1.state d.state && ok || bad "V10: save, load, save differs: $(cat err.txt)"
# and a settling bed without feed, saved while its pair list lives on
printf '%bseed 3\nchannel 0.01 0.03\nends closed closed\ngas 0\nspecies glass 2500\nsize glass loguniform min=0.4e-3 max=0.8e-3\nfeed z=0.015 hf=0.028\nstiffness overlap=0.05 vimp=1\ninsert glass 200\nrun 0.01\nsave e1.state\nrun 0.013\nsave ea.state\n' "$S" > v10e.mote
printf '%bload e1.state\nrun 0.013\nsave ec.state\n' "$S" > v10f.mote
"$MOTE" run v10e.mote > /dev/null 2> err.txt && grep -q '^pairlist 1 ' e1.state && "$MOTE" run v10f.mote > /dev/null 2>> err.txt && cmp -s ea.state ec.state && ok || bad "V10 with a pair list: $(cat err.txt; grep pairlist e1.state)"
# threads: 5000 particles (above the 4096 from which the passes use threads) in a gas felt by
# the solids give the same state on 1 and 2 threads; `threads` prints no note (contacts, exits
# and reorders on 1, 2 and 3 threads: test_sep_dem's `threads`)
printf '%bseed 4\nchannel 0.12 0.12\ngas 0.5\nspecies glass 2500\nsize glass loguniform min=0.8e-3 max=1.2e-3\nfeed z=0.06 hf=0.12\nstiffness overlap=0.05 vimp=1\ninsert glass 5000\nthreads %s\nrun 0.0003\nsave th%s.state\n' "$S" 1 1 > th1.mote
sed 's/^threads 1$/threads 2/; s/th1.state/th2.state/' th1.mote > th2.mote
"$MOTE" run th1.mote > th1.txt 2> err.txt && "$MOTE" run th2.mote > th2.txt 2>> err.txt && ok || bad "threads: $(cat err.txt)"
grep -q '^t=0.0003 .* N=5000 ' th1.txt && cmp -s th1.state th2.state && ok || bad "threads: the states on 1 and 2 threads differ: $(tail -n 1 th1.txt th2.txt)"
grep -qi 'thread' th2.txt err.txt && bad "threads: a note: $(cat th2.txt err.txt)" || ok
# a damaged state: located, nothing run, nothing written
head -c 3000 s1.state > cut.state
expect 1 "cut.mote:2:6: error: cut.state:" cut.mote "${S}load cut.state\nsave e.state\n"
[ ! -e e.state ] && ok || bad "a failed load wrote a state"
sed 's/^real W .*/real W -x/' s1.state > badw.state
expect 1 "badw.mote:2:6: error: badw.state:4: W: expected a real number, found '-x'" badw.mote "${S}load badw.state\n"
# the nested tables (species, classes, particles) are read by the same descriptor tables
line=$(grep -n '^p 3 ' s1.state | cut -d: -f1)
sed "${line}s/^p 3 [01] /p 3 2 /" s1.state > badsp.state
expect 1 "badsp2.mote:2:6: error: badsp.state:$line: SPECIES must be in [0, 1], found 2" badsp2.mote "${S}load badsp.state\n"
line=$(grep -n '^edge' s1.state | head -1 | cut -d: -f1)
sed "${line}s/ [^ ]*\$//" s1.state > badedge.state
expect 1 "badedge.mote:2:6: error: badedge.state:$line: expected 'edge EDGE NF NC MF MC NF_SPECIES NC_SPECIES MF_SPECIES MC_SPECIES NF_SPECIES NC_SPECIES MF_SPECIES MC_SPECIES': MC_SPECIES is missing" badedge.mote "${S}load badedge.state\n"
line=$(grep -n '^plate ' s1.state | cut -d: -f1)
sed "${line}s/^plate [0-9]* /plate 0 /" s1.state > badplate.state
expect 1 "badplate.mote:2:6: error: badplate.state:$line: NHOLES must be in [1, 100000000], found 0" badplate.mote "${S}load badplate.state\n"
# outputs: frames (and the movie when ffmpeg is here), snapshots, balance, profiles, tromp, live
# (the sanitized build writes as many of each over a fifth of the time: 3 s took 66 s there);
# o = frames dt, snapshots dt, balance dt, average_from, snapshot 2's time, the run
if [ -n "${MOTE_SANITIZED:-}" ]; then o="0.1 0.2 0.02 0.2 0.4 0.6"; else o="0.5 1 0.1 1 2 3"; fi
set -- $o
printf '%bchannel 0.05 1\ngas 1.5\ncollisions off\ntimestep 1e-3\nspecies quartz 2650\nsize quartz lognormal d50=150e-6 sigma=1.6 min=30e-6 max=600e-6\nspecies ore 4500\nsize ore lognormal d50=120e-6 sigma=1.6 min=30e-6 max=600e-6\nfeed z=0.5 rate=2e-5\nfeed_fraction quartz 0.7\nfeed_fraction ore 0.3\ngrid 0.2 0.004 pattern a=3e-3 p=5e-3 offset=1e-3\nslices 50\nframes fr %s\nsnapshots sn %s\nbalance bal.dat %s\nlive_png live.png\naverage_from %s\nrun %s\ntromp tr.dat\nprofiles pr.dat\nsummary\n' "$S" \
    "$1" "$2" "$3" "$4" "$6" > outs.mote
"$MOTE" run outs.mote > out.txt 2> err.txt && ok || bad "outs.mote: $(cat err.txt)"
[ "$(ls fr/frame_*.png | wc -l)" -eq 7 ] && ok || bad "frames: $(ls fr)"
if command -v ffmpeg > /dev/null 2>&1; then
    [ -s fr/movie.mp4 ] && grep -q "^frames: 7 frames fr/frame_\*.png, the movie fr/movie.mp4" out.txt && ok || bad "movie: $(cat out.txt err.txt)"
fi
[ "$(ls sn/snapshot_*.xyz | wc -l)" -eq 4 ] && ok || bad "snapshots: $(ls sn)"
# an extended XYZ: N, the lattice and properties line, N rows of 9 fields, ids unique
awk 'NR == 1 { n = $1 } NR == 2 { ok = /^Lattice="0.05 0 0 0 [0-9.e-]+ 0 0 0 1" Properties=species:S:1:species_name:S:1:id:I:1:pos:R:3:velo:R:3:radius:R:1 Time=/; if (match($0, / Time=[^ ]+ /)) { t = substr($0, RSTART + 6, RLENGTH - 7) + 0; ok = ok && t > t2 - 1e-9 * t2 && t < t2 + 1e-9 * t2 } else ok = 0 }
     NR > 2 { rows++; if (NF != 10 || $1 != "X" || ($2 != "quartz" && $2 != "ore") || seen[$3]++) bad = 1 }
     END { exit !(ok && rows == n && n > 100 && !bad) }' t2="$5" sn/snapshot_000002.xyz && ok || bad "xyz: $(head -3 sn/snapshot_000002.xyz)"
awk '/^# invariant_held = 1$/ { h = 1 } !/^#/ { rows++ } END { exit !(h && rows == 31) }' bal.dat && ok || bad "balance: $(head -5 bal.dat)"
# the balance's last row: fed_all = in_all + fines_all + coarse_all + lost_all
awk '!/^#/ { last = $0 } /^# columns:/ { for (i = 3; i <= NF; i++) col[$i] = i - 2 }
     END { split(last, v, " "); exit !(v[col["fed_all"]] == v[col["in_all"]] + v[col["fines_all"]] + v[col["coarse_all"]] + v[col["lost_all"]] && v[col["fed_all"]] > 0) }' bal.dat && ok || bad "balance row: $(tail -1 bal.dat)"
grep -q '^# columns: z_m eps_s eps_quartz eps_ore N v_z_m_s u_g_m_s rho_mix_kg_m3 minus_dp_dz_Pa_m p_minus_pH_Pa$' pr.dat && [ "$(grep -vc '^#' pr.dat)" -eq 50 ] && ok || bad "profiles: $(head -8 pr.dat)"
grep -q '^# columns: d_lo_m .* holdup_kg T_quartz T_ore$' tr.dat && grep -q '^# d50_m quartz = ' tr.dat && ok || bad "tromp species: $(grep '^#' tr.dat)"
# the live picture ends on the state the run ended in: the last frame's (same state, same options)
cmp -s live.png fr/frame_000006.png && ok || bad "live.png is not the run's last state (the last frame)"
for f in fr/frame_000006.png live.png tr.png pr.png; do
    [ "$(head -c 8 "$f" | od -An -tx1 | tr -d ' ')" = 89504e470d0a1a0a ] && ok || bad "$f is not a PNG"
done
grep -q '^balance: fed = in channel + fines + coarse + lost holds$' out.txt && ok || bad "summary: $(cat out.txt)"
# the shared words' forms: prefix= (its folder made; the movie P.mp4), snapshot file= now, and
# the messages for a series given both or neither of prefix= and dir=
# (short runs: a series by dir= and the same by prefix= give the same files)
SH='channel 0.05 1\ngas 1.5\ncollisions off\ntimestep 1e-3\nspecies quartz 2650\nsize quartz lognormal d50=150e-6 sigma=1.6 min=30e-6 max=600e-6\nfeed z=0.5 rate=2e-5\ninsert quartz 100\n'
mkdir snd
printf '%bsnapshot dir=snd dt=0.05\nrun 0.2\n' "$S$SH" > outd.mote
printf '%bframes prefix=pf/f dt=0.1 movie=off\nsnapshot prefix=ps/s dt=0.05\nsnapshot file=now.xyz\nrun 0.2\n' "$S$SH" > outp.mote
"$MOTE" run outd.mote > outd.txt 2> errd.txt && "$MOTE" run outp.mote > outp.txt 2> errp.txt &&
    [ "$(ls pf/f_*.png | wc -l)" -eq 3 ] && [ "$(ls ps/s_*.xyz | wc -l)" -eq 5 ] &&
    [ "$(head -1 now.xyz)" = 100 ] && cmp -s ps/s_000004.xyz snd/snapshot_000004.xyz && ok || bad "prefix=: $(cat errd.txt errp.txt; ls pf ps snd)"
expect 1 "pb.mote:2:1: error: snapshot: give prefix=P (files P_000000.xyz, ...) or dir=DIR (DIR/snapshot_000000.xyz, ...)" pb.mote "${S}snapshot dt=1\n"
expect 1 "pd.mote:2:" pd.mote "${S}frames dir=a prefix=b dt=1\n"
expect 1 "pf.mote:2:15: error: snapshot: file= writes one snapshot now" pf.mote "${S}snapshot file=a.xyz dt=1\n"
# the monitor is followed as it grows (issue 53): bal.dat.partial while a run writes it, gone
# when the complete file is there; a run stopped with SIGINT halfway leaves its rows so far in
# the partial file, readable, and the earlier complete file untouched
[ ! -e bal.dat.partial ] && ok || bad "bal.dat.partial left after a run that ended"
cp bal.dat bal.before
printf '%bchannel 0.05 1\ngas 1.5\ncollisions off\ntimestep 1e-3\nspecies quartz 2650\nsize quartz lognormal d50=150e-6 sigma=1.6 min=30e-6 max=600e-6\nfeed z=0.5 rate=2e-5\nmonitor file=bal.dat dt=0.01\nrun 100000\n' "$S" > long.mote
sigint_after_rows long.mote bal.dat.partial 5 long.out
[ "$sigint_rc" -eq 130 ] && grep -q "^mote: stopped by Ctrl-C (SIGINT)" long.out && ok || bad "the run was not stopped at a safe point by SIGINT: $(cat long.out)"
cmp -s bal.dat bal.before && ok || bad "the complete bal.dat changed under a run that was stopped"
awk '/^# columns:/ { n = NF - 2 } !/^#/ { rows++; if (NF != n) bad = 1 } END { exit !(n > 0 && rows >= 5 && !bad) }' bal.dat.partial &&
    grep -q '^# mote separator-balance 1$' bal.dat.partial && ok || bad "the stopped run's rows: $(head -c 600 bal.dat.partial)"
expect 1 "f1.mote:2:21: error: frames: expected 'size' or 'species' for color, found 'x'" f1.mote "${S}frames fr 0.1 color=x\n"
# the picture beside a table is an output too: a later command that writes it is reported
expect 0 "png.mote:8:1: warning: profiles: " png.mote "${S}channel 0.05 1\ngas 1\nspecies a 2500\nsize a mono d=1e-4\nfeed z=0.5\ntromp t.dat\nprofiles t.csv\n" check
grep -q "'.*t.png' is written more than once" err.txt && ok || bad "tromp and profiles of one stem: $(cat err.txt)"
# the words of an argument are the table's (enumerations, a number or a word)
expect 1 "w1.mote:2:11: error: ends: expected 'open' or 'closed' for TOP, found 'ajar'" w1.mote "${S}ends open ajar\n"
expect 1 "w2.mote:2:10: error: timestep: expected a real number or 'auto' for auto|DT, found 'fast'" w2.mote "${S}timestep fast\n"
expect 1 "w3.mote:2:10: error: timestep: auto|DT must be > 0, found -1" w3.mote "${S}timestep -1\n"
expect 1 "w4.mote:3:8: error: size: expected 'mono', 'lognormal', 'rosin_rammler', 'loguniform' or 'table' for TYPE, found 'gauss'" w4.mote "${S}species a 2500\nsize a gauss d=1e-3\n"
expect 0 "" w5.mote "${S}timestep auto nc=40\ncollisions off\nneighbours brute\ncoupling off\n"
expect 1 "f2.mote:2:8: error: frames: the directory that would hold 'nodir/fr' does not exist" f2.mote "${S}frames nodir/fr 0.1\n"
# bad input
expect 1 "b1.mote:11:1: error: run: the feed fractions must sum to 1, found 0.9 (a 0.5, b 0.4)" b1.mote "${S}channel 0.05 1\ngas 1.0\nspecies a 2500\nspecies b 1500\nsize a mono d=1e-4\nsize b mono d=2e-4\nfeed z=0.5 rate=0.001\nfeed_fraction a 0.5\nfeed_fraction b 0.4\nrun 1\n"
expect 1 "b2.mote:4:8: error: size: need 0 < d_min < d_max (found 0.0003 and 0.0001 m)" b2.mote "${S}channel 0.05 1\nspecies a 2500\nsize a loguniform min=3e-4 max=1e-4\n"
expect 1 "b3.mote:4:8: error: feed: z must lie inside the channel (0 < z < H = 1 m), found 2" b3.mote "${S}channel 0.05 1\ngas 1\nfeed z=2\n"
expect 1 "b4.mote:7:1: error: insert: the largest particle (0.002 m) does not fit the channel (0.001 m across)" b4.mote "${S}channel 0.001 1\ngas 1\nspecies a 2500\nsize a mono d=2e-3\nfeed z=0.5\ninsert a 10\n"
expect 1 "b5.mote:8:1: error: run: the time step 0.001 s is above the stability limit 3.25669e-07 s of the contacts (t_c,min / N_c, spec 2.8)" b5.mote "${S}channel 0.05 1\ngas 1\nspecies a 2500\nsize a mono d=1e-3\nfeed z=0.5\ntimestep 1e-3\nrun 1\n"
expect 1 "b6.mote:5:1: error: run: no gas upflow" b6.mote "${S}channel 0.05 1\nspecies a 2500\nsize a mono d=1e-4\nrun 1\n"
expect 0 "" sp1.mote "${S}species name=a density=2500\nspecies b 1500\nsize a mono d=1e-4\n" check
expect 1 "sp2.mote:2:11: error: species: density must be > 0, found -1" sp2.mote "${S}species a -1\n"
expect 1 "sp3.mote:2:9: error: species: a name without spaces, commas, '=', '#' or '\"'" sp3.mote "${S}species \"fine ore\" 2500\n"
expect 1 "b7.mote:4:6: error: size: no species 'b'" b7.mote "${S}channel 0.05 1\nspecies a 2500\nsize b mono d=1e-4\n"
expect 1 "b8.mote:3:8: error: size lognormal: give sigma=" b8.mote "${S}species a 2500\nsize a lognormal d50=1e-4 min=1e-5 max=1e-3\n"
expect 1 "b9.mote:5:1: error: run: species a has no size distribution" b9.mote "${S}channel 0.05 1\ngas 1\nspecies a 2500\nrun 1\n"
# grids: bad geometry, each located
printf '0.001 0.002\n0.0015 0.003\n' > holes.txt
expect 1 "g1.mote:3:1: error: grid 1: holes 1 and 2 overlap" g1.mote "${S}channel 0.05 1\ngrid 0.3 0.005 holes file=holes.txt\n"
expect 1 "g2.mote:3:26: error: grid: a hole of 0.06 m is not narrower than the channel (0.05 m across)" g2.mote "${S}channel 0.05 1\ngrid 0.3 0.005 pattern a=0.06 p=0.1\n"
expect 1 "g3.mote:8:1: error: run: grid 1: hole 1 is 0.0005 m wide, narrower than the finest particle (0.001 m): nothing could pass" g3.mote "${S}channel 0.05 1\ngas 1\nspecies a 2500\nsize a mono d=1e-3\ngrid 0.3 0.005 pattern a=0.5e-3 p=2e-3\nfeed z=0.5\nrun 1\n"
expect 1 "g4.mote:9:1: error: run: grids 1 (0.3 ... 0.305 m) and 2 (0.302 ... 0.307 m) overlap" g4.mote "${S}channel 0.05 1\ngrid 0.3 0.005 pattern a=1e-3 p=2e-3\ngrid 0.302 0.005 pattern a=1e-3 p=2e-3\ngas 1\nspecies a 2500\nsize a mono d=1e-4\nfeed z=0.5\nrun 1\n"
printf '0.001 0.002\n0.003 x\n' > holes2.txt
expect 1 "g5.mote:3:1: error: holes2.txt:2: value 2 is not a finite number" g5.mote "${S}channel 0.05 1\ngrid 0.3 0.005 holes file=holes2.txt\n"
expect 1 "g6.mote:3:27: error: grid: 'holes3.txt' does not exist and no earlier command writes it" g6.mote "${S}channel 0.05 1\ngrid 0.3 0.005 holes file=holes3.txt\n"
expect 1 "g7.mote:3:6: error: grid: the plate 0.998 ... 1.008 m does not fit the channel (H = 1 m)" g7.mote "${S}channel 0.05 1\ngrid 0.998 0.01 pattern a=1e-3 p=2e-3\n"
# explicit class edges from a file, and a table size distribution: three classes in the table
printf '1e-4\n2e-4\n3e-4\n4e-4\n' > edges.txt
printf '1e-4 0\n4e-4 1\n' > szok.txt
printf '%bchannel 0.05 1\ngas 1.0\ncoupling off\ncollisions off\ntimestep 1e-3\nspecies a 2500\nsize a table file=szok.txt\nclasses_file edges.txt\nfeed z=0.5\ninsert a 300\nrun 5\ntromp cf.dat\n' "$S" > cf.mote
"$MOTE" run cf.mote > /dev/null 2> err.txt && [ "$(grep -vc '^#' cf.dat)" -eq 3 ] && grep -q '^0.0001 0.0002 ' cf.dat && ok || bad "classes_file: $(cat err.txt; cat cf.dat)"
printf '1e-4\n3e-4\n2e-4\n' > edges2.txt
expect 1 "cf2.mote:2:14: error: edges2.txt:3: expected one class edge (m) per row, > 0 and increasing" cf2.mote "${S}classes_file edges2.txt\n"
# 3D from a script: a feed window and velocity in y, a grid, frames of a slab, snapshots
printf '%bdim 3\nchannel 0.02 0.08 D=0.015\nends open closed\ngas 2\nspecies glass 2500\nsize glass loguniform min=1e-3 max=1.5e-3\nfeed z=0.05 rate=0.005\nfeed_window 0.005 0.015 y1=0.004 y2=0.011\nfeed_velocity 0 0 vy=0.1\ngrid 0.02 0.002 pattern a=2e-3 p=4e-3 offset=1e-3\nstiffness overlap=0.05 vimp=3\nframes fr3 0.01 y1=0.005 y2=0.01 movie=off\nsnapshots sn3 0.02\nrun 0.05\nsummary\n' "$S" > d3.mote
"$MOTE" run d3.mote > out.txt 2> err.txt && grep -q '^t=0.05 .* N=1[0-9][0-9] fed=1[0-9][0-9] .* lost=0 ' out.txt && [ "$(ls fr3/frame_*.png | wc -l)" -eq 6 ] && [ ! -e fr3/movie.mp4 ] && ok || bad "3D: $(cat out.txt err.txt)"
awk 'NR == 2 { ok = /^Lattice="0.02 0 0 0 0.015 0 0 0 0.08"/ } NR > 2 { n++ } END { exit !(ok && n > 50) }' sn3/snapshot_000002.xyz && ok || bad "3D snapshot: $(head -3 sn3/snapshot_000002.xyz)"
expect 1 "fw.mote:3:26: error: feed_window: y1= and y2= are for 3D" fw.mote "${S}channel 0.05 1\nfeed_window 0.01 0.02 y1=0 y2=0.01\n"
expect 1 "b3b.mote:4:8: error: feed: z must lie inside the channel (0 < z < H = 1 m), found -0.1" b3b.mote "${S}channel 0.05 1\ngas 1\nfeed z=-0.1\n"
# profiles before anything was averaged: a runtime error at its line, no file
expect 2 "pf.mote:7:1: error: profiles: nothing averaged yet (run past average_from = 0 s first)" pf.mote "${S}channel 0.05 1\ngas 1\nspecies a 2500\nsize a mono d=1e-4\nfeed z=0.5\nprofiles pf.csv\n"
[ ! -e pf.csv ] && ok || bad "a failed profiles wrote a file"
# a size table with a bad row, located
printf '# d F\n1e-4 0\n2e-4 0.7\n3e-4 0.6\n' > sz.txt
expect 1 "sz.mote:4:19: error: sz.txt:4: the cumulative undersize must lie in [0, 1] and not decrease (found 0.6)" sz.mote "${S}channel 0.05 1\nspecies a 2500\nsize a table file=sz.txt\n"
# gas profiles: bad files, located
printf '0 1.2\n0.5 1.0\n0.4 0.9\n' > gp1.txt
expect 1 "gp1.mote:3:13: error: gp1.txt:3: the heights must increase (z = 0.4 after 0.5)" gp1.mote "${S}channel 0.05 1\ngas_profile gp1.txt\n"
printf '# z rho\n0 1.2\n1 -0.5\n' > gp2.txt
expect 1 "gp2.mote:3:13: error: gp2.txt:3: the gas density must be > 0, found -0.5" gp2.mote "${S}channel 0.05 1\ngas_profile gp2.txt\n"
expect 1 "gp3.mote:3:13: error: gas_profile: 'gp3.txt' does not exist and no earlier command writes it" gp3.mote "${S}channel 0.05 1\ngas_profile gp3.txt\n"
# a dilute run through a grid: particles reflect from the plate and its holes, none lost
printf '%bchannel 0.05 1\ngas 1.0\ncollisions off\nspecies quartz 2500\nsize quartz loguniform min=75e-6 max=300e-6 basis=number\ngrid 0.3 0.005 pattern a=2e-3 p=4e-3 offset=1e-3\nfeed z=0.5\ninsert quartz 2000\nrun 10\n' "$S" > grid.mote
"$MOTE" run grid.mote > out.txt 2> err.txt && ok || bad "grid.mote failed: $(cat err.txt)"
grep -q '^grid 1: 1 pattern holes dropped for crossing a wall$' out.txt && ok || bad "dropped: $(cat out.txt)"
grep -q '^t=10 .* fed=2000 fines=[1-9][0-9]* coarse=[1-9][0-9]* lost=0 ' out.txt && ok || bad "grid run: $(cat out.txt)"
[ ! -e tromp_bad.csv ] && ok || bad "a failed script wrote a file"
# issue 33: the grid readers on short, empty and directory files (freed an uninitialised pointer)
printf '0.01 0.02\n0.04\n' > h1.txt
: > h2.txt
mkdir hd
expect 1 "gh1.mote:3:1: error: h1.txt:2: expected x1 x2 (m), found 1 value" gh1.mote "${S}channel 0.05 1\ngrid 0.3 0.01 holes file=h1.txt\n" check
expect 1 "gh2.mote:3:1: error: h2.txt: no holes in the file" gh2.mote "${S}channel 0.05 1\ngrid 0.3 0.01 holes file=h2.txt\n" check
expect 1 "gh3.mote:3:1: error: cannot read 'hd'" gh3.mote "${S}channel 0.05 1\ngrid 0.3 0.01 holes file=hd\n" check
# a pattern of 9e8 holes is refused with its memory, at check time; 9e6 holes check in linear time
expect 1 "gh4.mote:4:1: error: grid: the pattern makes 9e+08 holes (at most 1e+07 a plate: about 43.2 GB)" gh4.mote "${S}dim 3\nchannel 0.3 1 D=0.3\ngrid 0.3 0.01 pattern a=5e-6 p=1.00001e-5\n" check
# the feed clears closed ends by the radius (7 of 60 started inside an end: max_overlap 0.34)
printf '%bchannel 0.01 0.03\nends closed closed\ngas 0\nspecies glass 2500\nsize glass mono d=1e-3\nfeed z=0.005 hf=0.01\ninsert glass 60\nrun 0.001\n' "$S" > ends.mote
"$MOTE" run ends.mote > out.txt 2> err.txt && ok || bad "ends.mote: $(cat err.txt)"
awk '/^t=0.001 / { for (i = 1; i <= NF; i++) if ($i ~ /^max_overlap=/) { split($i, a, "="); v = a[2] } } END { exit !(v != "" && v + 0 < 0.05) }' out.txt && ok || bad "particles placed inside a closed end: $(tail -2 out.txt)"
! grep -q 'raise vimp' out.txt && ok || bad "the overlap note after placement: $(cat out.txt)"
# a feed that outruns its band says so
printf '%bchannel 0.01 0.05\nends closed closed\ngas 0\nspecies glass 2500\nsize glass mono d=1e-3\nfeed z=0.04 hf=0.002 rate=0.5\nrun 0.002\n' "$S" > back.mote
"$MOTE" run back.mote > out.txt 2> err.txt && grep -q '^warning: [0-9]* particles wait in the feed.s backlog' out.txt && ok || bad "no backlog warning: $(tail -3 out.txt) $(cat err.txt)"
# a channel given in 2D, then dim 3: the message says what is missing
expect 1 "dim3.mote:3:5: error: dim: the channel was given in 2D: a 3D channel needs its depth" dim3.mote "${S}channel 0.05 1\ndim 3\n" check
# hindered settling (issue 33): in this model a particle of a uniform suspension settles at
# v_t eps^chi in Stokes flow (no gas back-flow, no buoyancy against the suspension), so chi is the
# Richardson-Zaki exponent itself: 4.65 reproduces batch settling at small Reynolds numbers (Re
# here 3e-4), and 2.65 (Wen and Yu, for codes with back-flow and the pressure-gradient force)
# settles 20 to 80 % too fast. eps at each particle from the state's own particles, binned as
# the model bins them; v_t the Stokes velocity with the fluid's buoyancy; Schiller-Naumann's
# factor at the particle's Re. Deterministic: 0.5 % (the relaxation leaves 3e-5).
cat > chi_check.py <<'EOF'
import sys
path, n_rz = sys.argv[1], float(sys.argv[2])
W = D = 0.01; H = 0.06; K = 60; dz = H / K
rho_p, rho_g, mu, d, g = 2500.0, 1000.0, 1.0, 1e-3, 9.81
z, vz = [], []
for line in open(path):
    t = line.split()
    if t and t[0] == "p":
        z.append(float(t[7])); vz.append(float(t[10]))
vol = 3.141592653589793 / 6 * d ** 3
cell = [0.0] * K
for zi in z:
    q = zi / dz - 0.5
    if q <= 0: cell[0] += vol
    elif q >= K - 1: cell[K - 1] += vol
    else:
        k = int(q); f = q - k
        cell[k] += (1 - f) * vol; cell[k + 1] += f * vol
phi = [c / (W * D * dz) for c in cell]
vt = (rho_p - rho_g) * g * d * d / (18 * mu)
worst = 0.0
for zi, v in zip(z, vz):
    q = min(max(zi / dz - 0.5, 0), K - 1); k = int(min(q, K - 2)); f = q - k
    eps = 1 - ((1 - f) * phi[k] + f * phi[k + 1])
    re = rho_g * abs(v) * d / mu
    worst = max(worst, abs(v / (-vt * eps ** n_rz / (1 + 0.15 * re ** 0.687)) - 1))
print("%d particles, worst relative deviation from v_t eps^%g: %.3g" % (len(z), n_rz, worst))
sys.exit(not (len(z) == 1500 and worst < 0.005))
EOF
for chi in 4.65 2.65; do
    printf '%bdim 3\nseed 5\nchannel 0.01 0.06 D=0.01\nends closed closed\ngas 0 rho=1000 mu=1\ncollisions off\nslices 60\nrelax 1e-4\nhindered %s\nspecies glass 2500\nsize glass mono d=1e-3\nfeed z=0.03 hf=0.04\ninsert glass 1500\ntimestep 1e-4\nrun 0.2\nsave chi%s.state\n' "$S" "$chi" "$chi" > chi$chi.mote
    "$MOTE" run chi$chi.mote > /dev/null 2> err.txt || bad "chi$chi.mote: $(cat err.txt)"
done
python3 chi_check.py chi4.65.state 4.65 > out.txt && ok || bad "hindered 4.65 is not Richardson-Zaki with n = 4.65: $(cat out.txt)"
! python3 chi_check.py chi2.65.state 4.65 > out.txt && ok || bad "hindered 2.65 reproduced n = 4.65: $(cat out.txt)"
python3 chi_check.py chi2.65.state 2.65 > out.txt && ok || bad "hindered 2.65 does not settle at v_t eps^2.65: $(cat out.txt)"
# the parameter commands bound to the state's descriptors (mote_cmd_set): what each sets is
# the value save writes, words by their place (coupling off|on, collisions off|dem, neighbours
# cells|brute), and load gives it back
printf '%b' "${SEP_DILUTE}gravity 7.5\nrelax 0.25\ncoupling off\ncollisions off\nneighbours brute\nslices 40\nhindered 3.5\ndispersion 1e-4\nbrownian 300\nrestitution 0.5\nrestitution_wall 0.7\neps_gas_min 0.25\nsave par.state\nload par.state\nsave par2.state\n" > par.mote
if "$MOTE" run par.mote > par.out 2>&1; then ok; else bad "par.mote: $(tail -2 par.out)"; fi
got=$(grep -E '^(real (g|tau_eps|chi|D_t|T_gas|e_pp|e_pw|eps_gas_min)|int (coupling|dem|brute|K)) ' par.state | sort | tr '\n' ';')
want=$(printf '%s\n' 'real g 7.5' 'real tau_eps 0.25' 'int coupling 0' 'int dem 0' 'int brute 1' 'int K 40' 'real chi 3.5' 'real D_t 0.0001' 'real T_gas 300' 'real e_pp 0.5' 'real e_pw 0.69999999999999996' 'real eps_gas_min 0.25' | sort | tr '\n' ';')
[ "$got" = "$want" ] && ok || bad "bound parameters in the state file: $got, not $want"
cmp -s par.state par2.state && ok || bad "bound parameters: save, load, save differ"

# a run's estimate (check): its steps exactly (the run takes as many), the particles fed by the
# feed's rate and mean mass, the time and memory; a warning, under `mote run` too, before
# anything runs, when a run would take over an hour (a realistic sand feed: 20-500 um at
# 1 g/s, the automatic step of its smallest contacts)
printf '%bchannel 0.05 1\ngas 1.5\ncollisions off\ntimestep 1e-3\nspecies quartz 2650\nsize quartz mono d=1e-4\nfeed z=0.5 rate=1e-6\nrun 0.2\nrun 0.1\n' "$S" > est.mote
"$MOTE" check est.mote > out.txt 2> err.txt && [ ! -s err.txt ] &&
    grep -q "^est.mote:9:1: note: run 0.2 s: 200 steps of 0.001 s; 144 particles fed, about [0-9.]* in the channel on average" out.txt &&
    grep -q "^est.mote:10:1: note: run 0.1 s: 100 steps of 0.001 s; 72.1 particles fed" out.txt && ok || bad "estimate: $(cat out.txt err.txt)"
# (144 = 1e-6 kg/s x 0.2 s / (2650 pi (1e-4)^3 / 6 kg)); a closed channel whose feed stops half
# way through the run keeps all it was fed: on average 3/4 of them over the run, all at its end
printf '%bchannel 0.05 1\nends closed closed\ngas 1.5\ncollisions off\ntimestep 1e-3\nspecies quartz 2650\nsize quartz mono d=1e-4\nfeed z=0.5 rate=1e-6 stop=1\nrun 2\n' "$S" > estc.mote
"$MOTE" check estc.mote > out.txt 2> err.txt &&
    grep -q "^estc.mote:10:1: note: run 2 s: 2e+03 steps of 0.001 s; 721 particles fed, about 541 in the channel on average, 721 at the end" out.txt && ok || bad "estimate, closed: $(cat out.txt err.txt)"
"$MOTE" run est.mote > out.txt 2> err.txt && grep -q "^t=0.2 steps=200 " out.txt && grep -q "^t=0.3 steps=300 " out.txt && ok || bad "the estimated steps: $(grep '^t=' out.txt)"
SAND="${S}channel 0.05 1\ngas 1\nspecies sand 2650\nsize sand lognormal d50=100e-6 sigma=1.8 min=20e-6 max=500e-6\nfeed z=0.5 rate=0.001\nrun 1\n"
printf '%b' "$SAND" > sand.mote
"$MOTE" check sand.mote > out.txt 2> err.txt &&
    grep -q "^sand.mote:7:1: note: run 1 s: 8.6[0-9]e+07 steps of 1.16e-08 s; 2.9[0-9]e+06 particles fed" out.txt &&
    grep -q "^sand.mote:7:1: warning: run 1 s would take about [0-9.e+]* days (8.6[0-9]e+07 steps of 1.16e-08 s" err.txt && ok || bad "the sand feed's estimate: $(cat out.txt err.txt)"
expect 1 "sand2.mote:7:1: warning: run 1 s would take about" sand2.mote "${SAND}size nosuch mono d=1e-4\n"
grep -q "sand2.mote:8:6: error: size: no species 'nosuch'" err.txt && ! grep -q "^t=" out.txt && ok || bad "the warning before a failed check: $(cat out.txt err.txt)"

# parcels (dilute): 10 particles a parcel give the partition of one particle each, within the
# statistical error: in each class the fraction of those classified that went to the coarse
# (n_coarse / (n_fines + n_coarse), binomial) differs by at most 3 sigma, sigma^2 = p (1 - p)
# (1/n_1 + 1/n_10) with the pooled p of Agresti and Coull (x + 2) / (n + 4) (counts of a few:
# Am. Stat. 52, 119, 1998); a size range about the cut (d0* = 203 um) and strong dispersion,
# so that most classes are neither all fines nor all coarse. Also the mass fed to within one
# parcel (rate x time), the balance; refused with collisions; kept by save and load
PW="${S}seed 7\nchannel 0.05 1\ngas 1.5\ncollisions off\ntimestep 1e-3\nspecies quartz 2650\nsize quartz loguniform min=150e-6 max=300e-6\nfeed z=0.5 rate=1e-5\ndispersion 0.05\nclasses 12 min=150e-6 max=300e-6\n"
printf '%brun 2\nreset_stats\nrun 4\ntromp file=pw1.dat\nsummary\n' "$PW" > pw1.mote
printf '%bparcel 10\nrun 2\nreset_stats\nrun 4\ntromp file=pw10.dat\nsummary\nsave pw10.state\n' "$PW" > pw10.mote
"$MOTE" run pw1.mote > pw1.out 2> err.txt && "$MOTE" run pw10.mote > pw10.out 2>> err.txt && ok || bad "parcels: $(cat err.txt)"
paste pw1.dat pw10.dat | awk '!/^#/ && NF == 22 { n++; f1 = $6; c1 = $7; f2 = $17; c2 = $18
    n1 = f1 + c1; n2 = f2 + c2; if (n1 == 0 || n2 == 0) next
    cmp++; p = (c1 + c2 + 2) / (n1 + n2 + 4); s = sqrt(p * (1 - p) * (1 / n1 + 1 / n2))
    d = c1 / n1 - c2 / n2; if (d < 0) d = -d
    if (d > 3 * s) { bad = 1; print "class", n, c1 "/" n1, c2 "/" n2 }
    if (c1 > 0 && f1 > 0) mid++ } END { exit !(n == 12 && cmp == 12 && !bad && mid >= 3) }' > cmp.txt && ok || bad "parcel 10 against 1: $(cat cmp.txt; grep -v '^#' pw1.dat pw10.dat)"
for w in 1 10; do
    sed -n 's/^species quartz: fed \([0-9]*\) (\([^ ]*\) kg).*/\1 \2/p' pw$w.out | awk -v w=$w '{ mmax = 2650 * 3.14159265 / 6 * 3e-4 ^ 3; d = $2 - 1e-5 * 6; if (d < 0) d = -d; exit !(d <= w * mmax && $1 > 0) }' && ok || bad "parcel $w: the mass fed $(grep '^species' pw$w.out), not 6e-5 kg to within one parcel"
    grep -q "^balance: fed = in channel + fines + coarse + lost holds" pw$w.out && ok || bad "parcel $w: the balance: $(cat pw$w.out)"
done
n1=$(sed -n 's/^species quartz: fed \([0-9]*\) .*/\1/p' pw1.out) n10=$(sed -n 's/^species quartz: fed \([0-9]*\) .*/\1/p' pw10.out)
awk -v a="$n1" -v b="$n10" 'BEGIN { exit !(b > 0.08 * a && b < 0.12 * a) }' && ok || bad "parcel 10: $n10 parcels fed against $n1 particles"
grep -q '^real parcel 10$' pw10.state && ok || bad "the state has no 'real parcel 10'"
printf '%bload pw10.state\nsave pw10b.state\n' "$S" > pwl.mote
"$MOTE" run pwl.mote > out.txt 2> err.txt && cmp -s pw10.state pw10b.state && ok || bad "parcel: load, save differ: $(cat err.txt)"
expect 1 "pwd.mote:7:1: error: run: parcel 10 with collisions dem: a parcel would collide as one particle of its size" pwd.mote "${S}channel 0.05 1\ngas 1.5\nspecies quartz 2650\nsize quartz mono d=1e-4\nparcel 10\nrun 0.01\n" check

# contact hertz: bad input is a located error before anything runs, nothing written
HZ="${S}dim 3\nchannel 0.02 0.06 D=0.02\nends closed closed\ngas 0 rho=0 mu=0\n"
HZE="size glass mono d=2e-3\nfeed z=0.04 hf=0.02\ncontact hertz\ninsert glass 10\nrun 0.001\nsave hz.state\n"
expect 1 "hz1.mote:6:42: error: species: nu must be in (-1, 0.5), found 0.5" hz1.mote "${HZ}species name=glass density=2500 E=5e6 nu=0.5\n$HZE"
expect 1 "hz2.mote:10:1: error: insert: contact hertz: species glass has no Young's modulus (species name=glass density=2500 E=PASCAL nu=RATIO)" hz2.mote "${HZ}species name=glass density=2500\n$HZE"
expect 1 "hz3.mote:7:10: error: friction: MU must be >= 0, found -0.1" hz3.mote "${HZ}species name=glass density=2500 E=5e6\nfriction -0.1\n$HZE"
expect 1 "hz4.mote:7:27: error: friction_pair: MU must be >= 0, found -1" hz4.mote "${HZ}species name=glass density=2500 E=5e6\nfriction_pair glass glass -1\n$HZE"
expect 1 "hz5.mote:7:24: error: wall_material: nu must be in (-1, 0.5), found 0.7" hz5.mote "${HZ}species name=glass density=2500 E=5e6\nwall_material E=1e9 nu=0.7\n$HZE"
expect 1 "hz6.mote:11:1: error: insert: contact hertz with collisions off: nothing would collide (collisions dem)" hz6.mote "${HZ}species name=glass density=2500 E=5e6\ncollisions off\n$HZE"
expect 1 "hz7.mote:7:28: error: contact: restitution= goes with hertz" hz7.mote "${HZ}species name=glass density=2500 E=5e6\ncontact linear restitution=liggghts\n$HZE"
[ ! -e hz.state ] && ok || bad "a refused hertz script wrote its state"
# a hertz state: its springs and rotation read back exactly (save, load, save); a spring whose
# ids are out of order, or springs in a state of the linear law: located errors, nothing run
printf '%bspecies name=glass density=2500 E=5e6\nsize glass mono d=2e-3\nfeed z=0.02 hf=0.03\ncontact hertz\nfriction 0.5\ninsert glass 60\nrun 0.2\nsave hzs.state\n' "$HZ" > hzs.mote
printf '%bload hzs.state\nsave hzs2.state\n' "$S" > hzs2.mote
"$MOTE" run hzs.mote > /dev/null 2> err.txt && "$MOTE" run hzs2.mote > /dev/null 2>> err.txt && cmp -s hzs.state hzs2.state &&
    grep -q '^springs [1-9]' hzs.state && ok || bad "hertz state: save, load, save: $(cat err.txt; grep '^springs' hzs.state)"
line=$(grep -n '^h ' hzs.state | head -1 | cut -d: -f1)
awk -v l="$line" 'NR == l { t = $2; $2 = $3; $3 = t } { print }' hzs.state > hzbad.state
expect 1 "hzb1.mote:2:6: error: hzbad.state:$line: a spring's ids must be in increasing order" hzb1.mote "${S}load hzbad.state\nrun 0.001\n"
sed 's/^int hertz 1$/int hertz 0/' hzs.state > hzlin.state
expect 1 "hzb2.mote:2:6: error: hzlin.state:" hzb2.mote "${S}load hzlin.state\nrun 0.001\n"
grep -q "springs are kept only with contact hertz" err.txt && ok || bad "springs in a linear state: $(cat err.txt)"
# stiffness overlap= means nothing to contact hertz: a warning before anything runs, once
printf '%bspecies name=glass density=2500 E=5e6\nstiffness overlap=0.1\n%brun 0.001\n' "$HZ" "$HZE" > hzw.mote
"$MOTE" check hzw.mote > out.txt 2> err.txt && [ "$(grep -c 'warning: contact hertz takes its stiffness from the species' err.txt)" -eq 1 ] &&
    grep -q "^hzw.mote:12:1: warning: contact hertz takes its stiffness from the species' E and nu: stiffness overlap= and khat= do not apply" err.txt && ok || bad "hertz and stiffness: $(cat out.txt err.txt)"

# wall_mesh: a ramp (an ASCII STL sheet of two triangles) catches a pour; the log reports the
# mesh; the state keeps the wall and the springs at it (save, load, save: the same bytes)
printf 'solid ramp\n' > ramp.stl
for t in "0.0005 0.0005 0.03|0.0195 0.0005 0.02|0.0195 0.0195 0.02" "0.0005 0.0005 0.03|0.0195 0.0195 0.02|0.0005 0.0195 0.03"; do
    printf 'facet normal 0 0 1\nouter loop\n' >> ramp.stl
    echo "$t" | tr '|' '\n' | sed 's/^/vertex /' >> ramp.stl
    printf 'endloop\nendfacet\n' >> ramp.stl
done
printf 'endsolid ramp\n' >> ramp.stl
MW="${HZ}species name=glass density=2500 E=5e6\nsize glass mono d=2e-3\nfeed z=0.045 hf=0.02\ncontact hertz\nfriction 0.5\n"
printf '%bwall_mesh file=ramp.stl\ninsert glass 60\nrun 0.2\nsave mw.state\n' "$MW" > mw.mote
printf '%bload mw.state\nsave mw2.state\n' "$S" > mw2.mote
"$MOTE" run mw.mote > out.txt 2> err.txt && "$MOTE" run mw2.mote > /dev/null 2>> err.txt && cmp -s mw.state mw2.state &&
    grep -q '^mesh 4 2 0 ' mw.state && grep -q '^wall_springs [1-9]' mw.state &&
    grep -q '^wall_mesh: 2 triangles read; .* 0 closed and 1 open components' out.txt && ok ||
    bad "wall_mesh: a pour on a ramp, save, load, save: $(cat out.txt err.txt; grep '^mesh\|^wall_springs' mw.state)"
# the particles rest on the ramp: none below it (at x the ramp is at z = 0.03 - x / 1.9)
awk '$1 == "p" && $8 < 0.03 - ($6 - 0.0005) / 1.9 { n++ } END { exit n > 0 }' mw.state && ok || bad "wall_mesh: particles fell through the ramp"
# bad input: a located error at check, nothing run or written
printf '0 0 0 1 0 0 0 1 0\n0 0 nan 1 1 0 0 1 1\n' > bad.tri
MWE="insert glass 6\nrun 0.01\nsave mwe.state\n"
expect 1 "mw1.mote:11:16: error: wall_mesh: ramp.stl: solid=yes needs a closed mesh (every edge shared by exactly two triangles); 2 of its 2 triangles are in open components" mw1.mote "${MW}wall_mesh file=ramp.stl solid=yes\n$MWE" check
expect 1 "mw2.mote:11:16: error: wall_mesh: bad.tri:2: a coordinate that is not a finite number ('nan')" mw2.mote "${MW}wall_mesh file=bad.tri\n$MWE" check
expect 1 "mw3.mote:11:31: error: wall_mesh: omega= turns the wall about a line: give axis=X,Y,Z and centre=X,Y,Z too" mw3.mote "${MW}wall_mesh file=ramp.stl omega=3\n$MWE" check
expect 1 "mw4.mote:11:16: error: wall_mesh: ramp.stl: omega= needs an axis= of non-zero length" mw4.mote "${MW}wall_mesh file=ramp.stl omega=1 axis=0,0,0 centre=0,0,0\n$MWE" check
expect 1 "mw5.mote:11:16: error: wall_mesh: 'nothere.stl' does not exist and no earlier command writes it" mw5.mote "${MW}wall_mesh file=nothere.stl\n$MWE" check
expect 1 "mw6.mote:13:1: error: insert: wall_mesh (ramp.stl) needs dim 3 and collisions dem" mw6.mote "${MW}collisions off\nwall_mesh file=ramp.stl\n$MWE" check
W17=$(for k in $(seq 1 17); do printf 'wall_mesh file=ramp.stl\\n'; done)
expect 1 "mw7.mote:27:1: error: wall_mesh: at most 16 mesh walls" mw7.mote "${MW}${W17}$MWE" check
[ ! -e mwe.state ] && ok || bad "a refused wall_mesh script wrote its state"
# a solid wall in a state file: a triangle taken out makes the file refused at its line
printf 'v 0.005 0.005 0.01\nv 0.015 0.005 0.01\nv 0.005 0.015 0.01\nv 0.015 0.015 0.01\nv 0.005 0.005 0.02\nv 0.015 0.005 0.02\nv 0.005 0.015 0.02\nv 0.015 0.015 0.02\nf 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n' > cube.obj
printf '%bwall_mesh file=cube.obj solid=yes\ninsert glass 20\nrun 0.01\nsave mwc.state\n' "$MW" > mwc.mote
"$MOTE" run mwc.mote > /dev/null 2> err.txt && grep -q '^mesh 8 12 1 ' mwc.state && ok || bad "a solid cube wall: $(cat err.txt)"
awk '/^mesh 8 12 1 / { $3 = 11; l = NR } /^mt / { if (++t == 12) next } { print } END { print l > "mwc.line" }' mwc.state > mwc_open.state
expect 1 "mwc2.mote:2:6: error: mwc_open.state:$(cat mwc.line): cube.obj: solid=yes needs a closed mesh (every edge shared by exactly two triangles); 3 of its edges are not" mwc2.mote "${S}load mwc_open.state\nrun 0.001\n"
mote_test_end
