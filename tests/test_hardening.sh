#!/bin/sh
# test_hardening.sh: inputs that crashed or hung mote (found by fuzzing, issue 20) are clear
# errors or work: a state file with x = 1e20 (crashed the rebuild: a cell index out of int's
# range), a huge periodic coordinate (hung the wrapping loop), a speed of 1e300 (energy -nan,
# then a hang), a header declaring 10^8 particles over three lines (allocated 12.5 GB first);
# mixing boxes of 1e155 and of infinite width (passed the check, then overflowed the cell grid),
# tiny disks in a large box (the engine rebuilt at the same instant forever); `profile` with
# 10^9 samples (unbounded memory); issue 33: image bins per radius, a Galactica area of 10^7
# nodes, a script of 10^5 save lines (quadratic bookkeeping). Each runs under a time limit, so a
# hang fails. Then the
# smaller faults: an unhelpful 'bad header', raw bytes echoed, a device replaced by a file.
# Usage: sh tests/test_hardening.sh BUILD_DIR
NAME=test_hardening
. "$(dirname "$0")/lib.sh"
SRC=$(cd "$(dirname "$0")/.." && pwd)
mote_test_start "$1"

# state(NAME, FIRST_PARTICLE_LINE [, N]): the two-sphere example of docs/file-formats.md
state() {
    printf 'mote-state 1\nmodel hard-spheres\ndim 3\ngeometry slit\nbox 10 6 6\nn %s\ntime 0\ncollisions 0\nwall_collisions 0\nrng 910a2dec89025cc1 beeb8da1658eec67 f893a2eefb32555e 71c18690ee42c90b\nparticles x y z vx vy vz radius mass\n%s\n7 3 3 -1 1 -1 1 1\nend\n' \
        "${3:-2}" "$2" > "$1"
}

# limited STATUS PREFIX-OF-STDERR NAME TEXT: like expect, under a 60 s limit
limited() {
    printf '%b' "$4" > "$3"
    timeout 60 "$MOTE" run "$3" > out.txt 2> err.txt
    got=$?
    [ "$got" -eq "$1" ] && ok || bad "$3: exit status $got, expected $1 ($(head -c 300 err.txt))"
    case "$(cat err.txt)" in
        "$2"*) ok ;;
        *) bad "$3: stderr '$(head -c 300 err.txt)', expected it to start with '$2'" ;;
    esac
}

state far.state "1e20 3 3 1 -1 1 1 1"
limited 2 "far.mote:1:1: error: far.state:12: particle 0: x = 1e+20 is outside the walls" far.mote "load far.state\n"
state farneg.state "-1e20 3 3 1 -1 1 1 1"
limited 2 "farneg.mote:1:1: error: farneg.state:12: particle 0: x = -1e+20 is outside the walls" farneg.mote "load farneg.state\n"
state wrap.state "3 1e15 3 1 -1 1 1 1"
limited 0 "" wrap.mote "load wrap.state\nstep 10\nsave wrapped.state\n"
y=$(sed -n 12p wrapped.state | cut -d' ' -f2)
awk -v y="$y" 'BEGIN { exit !(y >= 0 && y < 6) }' && ok || bad "the huge y was not wrapped into the box: $y"
state fast.state "3 3 3 1e300 -1 1 1 1"
limited 2 "fast.mote:1:1: error: fast.state:12: particle 0: vx = 1.0000000000000001e+300: speeds above 1e100" fast.mote "load fast.state\n"
state many.state "3 3 3 1 -1 1 1 1" 100000000
limited 2 "many.mote:1:1: error: many.state:15: file ends early: n = 100000000, but only 3 lines follow" many.mote "load many.state\n"

H='model mixing-box\n'
limited 1 "huge.mote:4:1: error: place: box: 1e+155 x 1e+155 is more than 10^9 disk diameters" huge.mote "${H}box 0 1e155 0 1e155\ndisks 1 1\nplace\nrun 1\n"
limited 1 "inf.mote:3:1: error: place: box: inf x 1 is more than 10^9 disk diameters" inf.mote "${H}box -1e308 1e308 0 1\nplace\nrun 1\n"
limited 0 "" small.mote "${H}radius 0.001\ndisks 20 20\nplace\nrun 10\n"
grep -q '^N=40 t=10 ' out.txt && ok || bad "small.mote did not reach t = 10: $(tail -n 1 out.txt)"

limited 1 "dots.mote:2:14: error: profile: dots must be in [1, 1000000], found 1000000000" dots.mote "new 2 0.3\nprofile 0 24 1000000000 1 p.dat\n"

# found by `make fuzz`: a mixing-box state with two coincident disks hung the event integrator,
# which now refuses such a start; a disk faster than 10^6 m/s is refused at load
printf '%b' "${H}disks 5 5\nplace\nsave good.state\n" > mbsave.mote
"$MOTE" run mbsave.mote > /dev/null 2>&1
awk 'NR == 52 { print prev; next } { print; prev = $0 }' good.state > twins.state
limited 2 "twins.mote:3:1: error: run: the event integrator cannot start with overlapping disks (1 pairs" twins.mote "${H}load twins.state\nrun 0.01\n"
limited 0 "" twins2.mote "${H}load twins.state\nintegrator timestep\nrun 0.01\n"
awk 'NR == 52 { $3 = "2e6" } { print }' good.state > fast.mbstate
limited 2 "fastmb.mote:2:1: error: fast.mbstate:52: a velocity component above 10^6 m/s" fastmb.mote "${H}load fast.mbstate\n"

# smaller ones: the check-time look at a state file names the bad header value; bytes that
# are not UTF-8 are shown escaped; a device is never replaced by a file
state neg.state "3 3 3 1 -1 1 1 1" -1
expect 1 "neg.mote:1:6: error: neg.state:6: N: expected a non-negative integer, found '-1'" neg.mote "load neg.state\n" check
expect 1 "utf.mote:2:1: error: unknown command '\\xFF\\xFEstep'" utf.mote "new 2 0.3\n\377\376step 1\n" check
expect 2 "dev.mote:2:1: error: cannot write '/dev/null': it exists and is not a regular file" dev.mote "new 2 0.3\nsave /dev/null\n"
[ -c /dev/null ] && ok || bad "/dev/null is no longer a device"

# issue 33: counts a script can ask for are bounded before anything is allocated, and the
# bookkeeping of a long script is not quadratic (10^5 save lines took over a minute to check)
limited 1 "bins.mote:2:9: error: image: p must be in [1, 10000], found 10000000" bins.mote "new 8 0.3\nimage 1 10000000 F\n"
limited 1 "area.mote:2:1: error: generate area: 426 x 214 x 107 = 9754548 nodes is more than the 10^6" area.mote "model nbody\ngenerate area mu=425 b=0.5 c=0.25\n"
awk 'BEGIN { print "new 8 0.3"; for (i = 0; i < 100000; i++) printf "save s%d.txt\n", i }' > saves.mote
timeout 60 "$MOTE" check saves.mote > out.txt 2> err.txt && grep -q 'ok: 100001 commands' out.txt && ok || bad "10^5 save lines: $(tail -c 300 err.txt)"
# a script of more than 10^6 lines outside loops may still have a loop (only the lines that
# loops read count against their bound)
awk 'BEGIN { for (i = 0; i < 1000001; i++) print "echo a"; print "for k in 1 2\necho ${k}\nend" }' > lines.mote
timeout 60 "$MOTE" check lines.mote > out.txt 2> err.txt && grep -q 'ok: 1000003 commands' out.txt && ok || bad "10^6 lines and a loop: $(tail -c 300 err.txt)"
# ... nor with a numbered series beside them (each file is compared with the series only)
awk 'BEGIN { print "model mixing-box\nbox 0 2 0 1\npartition 1 0.02\nslit 0.5 0.1\nradius 0.01\ndisks 4 4\nv_init 1\nplace\nframes 1 f"; for (i = 0; i < 100000; i++) printf "snapshot s%d.png\n", i }' > snaps.mote
timeout 60 "$MOTE" check snaps.mote > out.txt 2> err.txt && grep -q 'ok: 100009 commands' out.txt && ok || bad "10^5 snapshot lines and frames: $(tail -c 300 err.txt)"
# found by `make fuzz` (issue 33): a mixing box with loss 1 (inelastic) and disks at 10^4 m/s:
# a pair left in contact approaching by less than an ulp of its speeds collided again and again
# at one instant (the change of velocity rounded away), a hang
cp "$SRC/fuzz/corpus/mb_state/timeout-inelastic-contact-below-an-ulp" ulp.state
limited 0 "" ulp.mote "model mixing-box\nload ulp.state\nkicks 8 1 0\nloss 1\nrun 0.01\n"
grep -q '^N=10 t=0.06 ' out.txt && ok || bad "the inelastic run did not reach t = 0.06: $(tail -n 1 out.txt)"
# an undefined error (one block's contact value) is written "nan", never "-nan" (the sign bit
# of 0/0), in a data file's header and on the result line
printf 'new 2 0.3\nstep 20\npressure 5 p.dat\n' > nan.mote
"$MOTE" run nan.mote > out.txt 2> err.txt && grep -q ' ± nan$' p.dat && ! grep -q -- '-nan' p.dat out.txt && ok ||
    bad "NaN written as: $(grep -h -- 'nan' p.dat out.txt | head -n 3)"

# issue 52: values that would make a state non-finite are refused where they are known (check
# time), and a state that cannot advance or turns non-finite is an error (exit 2) naming the
# cause, never a run without end or a success with E = nan
limited 1 "temp.mote:3:13: error: temperature: T must be in (0, 1e100], found 1e308" temp.mote "new 2 0.3\nstep 1\ntemperature 1e308\nsave t.state\n"
[ ! -e t.state ] && ok || bad "temperature 1e308: a state was written"
limited 1 "vinit.mote:7:8: error: v_init: V must be in [0, 1e6], found 1e200" vinit.mote "${H}box 0 0.4 0 0.2\npartition 0.2 0.01\nslit 0.1 0.04\nradius 0.004\ndisks 30 20\nv_init 1e200\nplace\nrun 0.05\n"
limited 1 "grav.mote:7:9: error: gravity: g must be in [-1e100, 1e100], found 1e200" grav.mote "${H}box 0 0.4 0 0.2\npartition 0.2 0.01\nslit 0.1 0.04\nradius 0.004\ndisks 30 20\ngravity 1e200\nplace\nrun 0.05\n"
limited 2 "grav2.mote:9:1: error: run: this run cannot finish: " grav2.mote "${H}box 0 0.4 0 0.2\npartition 0.2 0.01\nslit 0.1 0.04\nradius 0.004\ndisks 30 20\ngravity 1e90\nplace\nrun 0.05\nsave g.state\n"
grep -q "so it would need about [0-9.e+]* events (the disks move too fast for the box" err.txt && [ ! -e g.state ] && ok || bad "gravity 1e90: $(cat err.txt; ls)"
S='model separator\nchannel 0.05 1\ngas 1e300\ncoupling off\ncollisions off\nspecies quartz 2500\nsize quartz loguniform min=75e-6 max=300e-6 basis=number\nfeed z=0.5\n'
# (the separator's run that cannot finish is known when it is checked: refused before anything
# runs, exit 1; the run itself refuses it too, should its step change)
limited 1 "gas.mote:10:1: error: run: the time step 6e-304 s would take 1.7e+301 steps to reach t = 0.01 s: this run cannot finish" gas.mote "${S}insert quartz 200\nrun 0.01\n"
limited 2 "gas2.mote:11:1: error: run: 200 particles were lost by t = 0.01 s (beyond a side wall, inside a plate, or not finite" gas2.mote "${S}timestep 1e-3\ninsert quartz 200\nrun 0.01\n"

mote_test_end
