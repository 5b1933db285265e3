#!/bin/sh
# test_states.sh BUILD_DIR: state files written by an earlier version still load (issue 34).
# tests/fixtures/states holds states written by mote as of 2026-11-27 (commit 5a2e365):
# hard spheres in 3D and 2D, the mixing box, nbody and the separator, and a Galactica
# checkpoint with its control file. Each must load, save again byte for byte (so every field is
# read and written back the same; nbody's in its version-2 form and the separator's in its
# version-1 form, below), and run on; the checkpoint must be rewritten unchanged by
# `galactica edit` with its own value and a relaunch must resume from it. Regenerate nothing:
# a change of format must keep reading these files.
NAME=states
. "$(dirname "$0")/lib.sh"
FX=$(cd "$(dirname "$0")" && pwd)/fixtures/states
mote_test_start "$1"

# An nbody state of version 4 (each integrator's own lines) written in the fixtures' version-2
# layout (tests/nbody_state.awk): the fixtures' fields must then come back byte for byte.
nbody_v2() { awk -v to=2 -f "$FX/../../nbody_state.awk" "$1"; }
# A separator state of version 4 in the fixture's version-1 layout: version 2 added one line,
# `real parcel W` (1 when read from version 1: one particle each); version 3 the contact law's
# lines (read from older files as the linear law: no friction or cohesion, E 0 and nu 0.3 per
# species, no pair overrides, no springs); version 4 the mesh walls and their springs (none)
sep_v1() {
    sed '1s/^mote-state 4$/mote-state 1/; /^meshes 0$/d; /^wall_springs 0$/d; /^real parcel 1$/d; /^real mu_pp 0$/d; /^real mu_pw -1$/d
         /^real mur_pp 0$/d; /^real mur_pw -1$/d; /^real E_w 0$/d; /^real nu_w 0$/d
         /^int hertz 0$/d; /^int e_true 1$/d; /^real coh_pp 0$/d; /^real coh_pw -1$/d
         /^mupair -1/d; /^murpair -1/d; /^cohpair -1/d; /^springs 0$/d
         /^sp /s/ 0 0\.29999999999999999$//' "$1"
}

# state MODEL FILE RUN: load FILE, save it again (must be identical, an nbody state after
# nbody_v2), then RUN a little
state() {
    m=$1 f=$2 go=$3
    cp "$FX/$f" "$f"
    printf 'model %s\nload %s\nsave re_%s\n%s\n' "$m" "$f" "$f" "$go" > "r_$f.mote"
    if "$MOTE" run "r_$f.mote" > "r_$f.out" 2>&1; then ok; else bad "$f: $(tail -3 "r_$f.out")"; fi
    if [ "$m" = "nbody gravity" ]; then
        nbody_v2 "re_$f" > "re2_$f" && mv "re2_$f" "re_$f"
    fi
    if [ "$m" = separator ]; then
        grep -q '^real parcel 1$' "re_$f" && ok || bad "$f: saved again without 'real parcel 1'"
        sep_v1 "re_$f" > "re2_$f" && mv "re2_$f" "re_$f"
    fi
    cmp -s "$FX/$f" "re_$f" && ok || bad "$f: saved again it differs: $(diff "$FX/$f" "re_$f" | head -4)"
}
state hard-spheres hs.state "step 2"
state hard-spheres hs2d.state "step 2"
state mixing-box mb.state "run 0.1"
state "nbody gravity" nbody.state "integrate steps=3"
state separator sep.state "run 0.005"

# what was loaded is what was saved: the times and counts in the status after load
grep -q "collisions=" r_hs.state.out && ok || bad "hs: no status after load: $(head -3 r_hs.state.out)"
grep -q "^load: 20 disks at t = 0.5 s" r_mb.state.out && ok || bad "mb: $(grep '^load' r_mb.state.out)"
grep -q "^load: 4 bodies at T = .* (step 5) from" r_nbody.state.out && ok || bad "nbody: $(grep '^load' r_nbody.state.out)"
grep -q "^load: read .*sep.state (t = 0.01 s, 62 particles)" r_sep.state.out && ok || bad "separator: $(grep '^load' r_sep.state.out)"

# the Galactica checkpoint: rewritten unchanged by an edit to its own value, then resumed
mkdir gal && cp "$FX/galactica/galgon4" "$FX/galactica/galacf26.dat" gal/
(cd gal && "$MOTE" galactica edit Kl3=100 > edit.txt 2>&1) && ok || bad "galactica edit: $(cat gal/edit.txt)"
nbody_v2 gal/galgon4 > gal/galgon4.v2 && cmp -s "$FX/galactica/galgon4" gal/galgon4.v2 && ok || bad "galgon4 rewritten by edit differs: $(diff "$FX/galactica/galgon4" gal/galgon4.v2 | head -4)"
(cd gal && "$MOTE" galactica > out.txt 2>&1) && ok || bad "galactica relaunch: $(tail -3 gal/out.txt)"
grep -q "resuming from galgon4 at step 200" gal/out.txt && ok || bad "the relaunch did not resume at step 200: $(head -3 gal/out.txt)"
grep -q "^galactica: 400 steps done" gal/out.txt && ok || bad "the relaunch did not run to step 400: $(tail -2 gal/out.txt)"

mote_test_end
