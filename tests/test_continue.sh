#!/bin/sh
# test_continue.sh: a save changes nothing, and a run continued from a saved state is the run that
# never stopped. For commands A and B, three scripts run in three directories:
#     A; B                    (two comment lines where the others save and load)
#     A; save F; B
#     A; save F; load F; B
# and every file they write (states, data files with their headers, pictures), except F itself,
# must be byte-identical, as must the status line after B; and a second script that loads F and
# runs B ends in the same state. The cases cover the 3D slit, the periodic cube, 2D slits and
# boxes, compression, every measurement, a trajectory dumped across the save, and the mixing
# box (both integrators, with samplers running across the save).
# Usage: sh tests/test_continue.sh BUILD_DIR
NAME=test_continue
. "$(dirname "$0")/lib.sh"
mote_test_start "$1"

# three_ways CASE MODEL_AND_SETUP A B: the three scripts, compared.
three_ways() {
    case_name=$1 setup=$2 a=$3 b=$4
    mkdir "$case_name" && cd "$case_name" || exit 1
    for v in plain save load; do
        mkdir "$v"
        case $v in
        plain) mid='# (no save here)\n# (no load here)' ;;
        save) mid='save "ck.state"\n# (no load here)' ;;
        load) mid='save "ck.state"\nload "ck.state"' ;;
        esac
        printf '%b\n' "$setup\n$a\n$mid\n$b\nsave \"final.state\"" > "$v/s.mote"
        (cd "$v" && "$MOTE" run s.mote > out.txt 2> err.txt) ||
            bad "$case_name/$v: mote failed: $(cat "$v/err.txt")"
        rm -f "$v/ck.state"
        tail -n 1 "$v/out.txt" > "$v/last_status.txt"
        rm -f "$v/out.txt" "$v/err.txt" "$v/s.mote"
    done
    # a fresh process that loads the checkpoint and runs B ends in the same state
    mkdir resume
    model_line=$(printf '%b\n' "$setup" | grep '^model ' || true)
    printf '%b\n' "$setup\n$a\nsave \"ck.state\"" > resume/s1.mote
    printf '%b\n' "$model_line\nload \"ck.state\"\n$b\nsave \"final.state\"" > resume/s2.mote
    (cd resume && "$MOTE" run s1.mote > /dev/null 2> err.txt && "$MOTE" run s2.mote > out.txt 2>> err.txt) ||
        bad "$case_name/resume: mote failed: $(cat resume/err.txt)"
    cmp -s plain/final.state resume/final.state && ok ||
        bad "$case_name: the resumed run's final state differs"
    [ "$(tail -n 1 resume/out.txt)" = "$(cat plain/last_status.txt)" ] && ok ||
        bad "$case_name: the resumed run's last status differs"
    rm -rf resume
    [ -s plain/final.state ] && ok || bad "$case_name: no final state"
    for v in save load; do
        if [ "$(ls plain)" = "$(ls $v)" ]; then ok; else
            bad "$case_name: plain wrote $(ls plain | tr '\n' ' '), $v wrote $(ls $v | tr '\n' ' ')"
        fi
        for f in plain/*; do
            g=$v/${f#plain/}
            if cmp -s "$f" "$g"; then ok; else
                bad "$case_name: $f and $g differ: $(diff "$f" "$g" 2>/dev/null | head -n 3 | tr '\n' ' ')"
            fi
        done
    done
    cd .. || exit 1
}

# the issue's example: 3D slit, steps on both sides
three_ways slit3d 'seed 7\nnew 2 0.3' 'step 50' 'step 50'
# compression before and after, then the wall-side measurements
three_ways compress 'seed 3\nnew 3 0.35' 'step 5\ncompress_left_wall 0.38 0.01 2' \
    'compress_right_wall 0.40 0.01 2\nimage 3 4 image.dat\nprofile 0 2 200 2 layer.dat'
# measurements on both sides of the save (their files must not differ either)
three_ways measure 'seed 11\nnew 3 0.4' 'step 3\npressure 2 p1.dat\norder 2 o1.dat' \
    'pressure 3 p2.dat\nchempot 2 50 mu.dat\norder 2 o2.dat\nstep 4'
# a trajectory being dumped across the save, and a snapshot after it
three_ways dump 'seed 4\nnew 2 0.35' 'dump 2 t.xyz\nstep 5' 'step 5\nsnapshot s.xyz'
# periodic cube: wrapped coordinates
three_ways bulk 'seed 5\nbulk 108 0.45' 'step 20\ntemperature 2' 'step 20\npressure 2 p.dat'
# 2D slit and 2D periodic box
three_ways disks 'seed 2\nnew_disks 10 12 0.5' 'step 30' 'step 30\nimage 2 4 im.dat'
three_ways bulkdisks 'seed 9\nbulk_disks 100 0.55' 'step 25' 'step 25\npressure 2 p.dat'

# the mixing box: event integrator with gravity, loss and kicks, samplers running across
mb='model mixing-box\nseed 4\nbox 0 0.4 0 0.2\npartition 0.2 0.01\nslit 0.1 0.04\nradius 0.004\ndisks 60 40\nv_init 1\nloss 0.1\ngravity 2\nkicks 0.05 0 0.02\nplace'
three_ways mb_event "$mb" 'record 0.05 rec.dat\ndensity_y 0.1 10 dens.dat\nrun 0.37' \
    'run 0.4\nsnapshot end.xyz'
# parameters changed after the last run take effect at the next one, loaded or not
three_ways mb_collisions "$mb" 'run_collisions 300 10\nloss 0.3\ngravity 5\nt_c 0.001' \
    'run_collisions 200 10\nrun 0.1'
# (in the time-stepped mode a sample time ends a step early, so the resumed script, which has
# no sampler running, would step differently: its sampler starts after the save)
three_ways mb_timestep "$mb\nintegrator timestep" 'run 0.23' 'record 0.05 rec.dat\nrun 0.2'

mote_test_end
