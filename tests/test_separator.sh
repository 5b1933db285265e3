#!/bin/sh
# test_separator.sh: the separator model through the `mote` program: the dilute cut size (spec
# 4 V2) from a script with its Tromp table, and bad input: each a located error before anything
# runs, nothing written.
# Usage: sh tests/test_separator.sh [BUILD_DIR]   (default: build)
NAME=separator
. "$(dirname "$0")/lib.sh"
mote_test_start "$1"

S='model separator\n'
printf '%bchannel 0.05 1\ngas 1.0\ncoupling off\ncollisions off\nspecies quartz 2500\nsize quartz loguniform min=75e-6 max=300e-6 basis=number\nfeed z=0.5\nclasses 25 min=75e-6 max=316.2277660e-6\ntimestep 1e-3\ninsert quartz 4000\nrun 30\ntromp tromp.csv\n' "$S" > v2.mote
"$MOTE" run v2.mote > out.txt 2> err.txt && ok || bad "v2.mote failed: $(cat err.txt)"
grep -q '^t=30 steps=30000 dt=0.001 N=[0-9]* fed=4000 fines=[0-9]* coarse=[0-9]* lost=0 backlog=0 d50=' out.txt && ok || bad "status: $(grep '^t=' out.txt)"
awk '/^# d50_m = / { d = $4 } /^# kappa = / { k = $4 } /^# d0_star_m quartz = / { s = $5 }
     END { r = d / 151.84e-6 - 1; exit !(r * r <= 0.0004 && k >= 0.9441 && k <= 1 && s > 151.83e-6 && s < 151.85e-6) }' tromp.csv && ok || bad "tromp: $(grep '^#' tromp.csv)"
[ "$(grep -vc '^#' tromp.csv)" -eq 25 ] && ok || bad "tromp rows: $(grep -vc '^#' tromp.csv)"
# the same script and seed give the same file
"$MOTE" run v2.mote > /dev/null 2>&1 && cp tromp.csv t1.csv && "$MOTE" run v2.mote > /dev/null 2>&1 && cmp -s t1.csv tromp.csv && ok || bad "two runs differ"
# DEM: 300 glass beads settle in a closed box without gas flow; none lost, the overlap within
# twice delta_f, the status reports the contact fields
printf '%bchannel 0.02 0.06\nends closed closed\ngas 0\nspecies glass 2500\nsize glass mono d=1e-3\nfeed z=0.03 hf=0.05\ninsert glass 300\nrun 0.005\n' "$S" > dem.mote
"$MOTE" run dem.mote > out.txt 2> err.txt && ok || bad "dem.mote failed: $(cat err.txt)"
grep -q '^t=0.005 steps=[0-9]* dt=3.25669e-07 N=300 fed=300 fines=0 coarse=0 lost=0 backlog=0 d50=nan kappa=nan eps_max=[0-9.]* max_overlap=[0-9.e-]* fast_moves=0$' out.txt && ok || bad "dem status: $(cat out.txt)"
awk -F'max_overlap=' '/^t=/ { split($2, a, " "); exit !(a[1] <= 0.1) }' out.txt && ok || bad "dem overlap: $(cat out.txt)"
# bad input
expect 1 "b1.mote:11:1: error: run: the feed fractions must sum to 1, found 0.9 (a 0.5, b 0.4)" b1.mote "${S}channel 0.05 1\ngas 1.0\nspecies a 2500\nspecies b 1500\nsize a mono d=1e-4\nsize b mono d=2e-4\nfeed z=0.5 rate=0.001\nfeed_fraction a 0.5\nfeed_fraction b 0.4\nrun 1\n"
expect 1 "b2.mote:4:8: error: size: need 0 < d_min < d_max (found 0.0003 and 0.0001 m)" b2.mote "${S}channel 0.05 1\nspecies a 2500\nsize a loguniform min=3e-4 max=1e-4\n"
expect 1 "b3.mote:4:8: error: feed: z must lie inside the channel (0 < z < H = 1 m), found 2" b3.mote "${S}channel 0.05 1\ngas 1\nfeed z=2\n"
expect 1 "b4.mote:7:1: error: insert: the largest particle (0.002 m) does not fit the channel (0.001 m across)" b4.mote "${S}channel 0.001 1\ngas 1\nspecies a 2500\nsize a mono d=2e-3\nfeed z=0.5\ninsert a 10\n"
expect 1 "b5.mote:8:1: error: run: the time step 0.001 s is above the stability limit 3.25669e-07 s of the contacts (t_c,min / N_c, spec 2.8)" b5.mote "${S}channel 0.05 1\ngas 1\nspecies a 2500\nsize a mono d=1e-3\nfeed z=0.5\ntimestep 1e-3\nrun 1\n"
expect 1 "b6.mote:5:1: error: run: no gas upflow" b6.mote "${S}channel 0.05 1\nspecies a 2500\nsize a mono d=1e-4\nrun 1\n"
expect 1 "b7.mote:4:6: error: size: no species 'b'" b7.mote "${S}channel 0.05 1\nspecies a 2500\nsize b mono d=1e-4\n"
expect 1 "b8.mote:3:8: error: size lognormal: give sigma=" b8.mote "${S}species a 2500\nsize a lognormal d50=1e-4 min=1e-5 max=1e-3\n"
expect 1 "b9.mote:5:1: error: run: species a has no size distribution" b9.mote "${S}channel 0.05 1\ngas 1\nspecies a 2500\nrun 1\n"
[ ! -e tromp_bad.csv ] && ok || bad "a failed script wrote a file"
mote_test_end
