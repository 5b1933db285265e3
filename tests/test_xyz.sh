#!/bin/sh
# test_xyz.sh: the hard-sphere model's extended XYZ files (`snapshot`, `dump`) read back by an
# independent reader, ASE (Debian's python3-ase, installed by scripts/setup.sh): every frame's
# positions, velocities, radii, box, pbc and time agree with the state saved at the same moment
# (to the last bit), the trajectory has its frames at the right collision counts, a run with a
# dump ends in the same state as without, and the local order is right where it is known
# exactly: a perfect FCC crystal (q6 = 0.57452, every particle solid), a hexagonal disk lattice
# (|psi6| = 1, every disk ordered), a fluid at eta 0.40 (almost no solid particle); and a
# mixing-box snapshot (He and Ar for the two colours) against its saved state.
# Usage: sh tests/test_xyz.sh BUILD_DIR
NAME=test_xyz
. "$(dirname "$0")/lib.sh"
mote_test_start "$1"
PY=/usr/bin/python3
if ! $PY -c 'import ase.io' 2>/dev/null; then
    bad "ASE is missing: run scripts/setup.sh (Debian package python3-ase)"
    mote_test_end
    exit 1
fi

run() { "$MOTE" run "$1" > out.txt 2> err.txt || bad "$1: $(cat err.txt)"; }

# 3D slit: a dump across steps and a compression, a snapshot and a save at the end
cat > slit.mote <<'S'
seed 5
new 3 0.40
save s0.state
dump 3 traj.xyz
step 3
save s1.state
compress_left_wall 0.43 0.05 1
step 2
snapshot end.xyz
save end.state
S
run slit.mote
# the same without the dump
grep -v 'dump' slit.mote | sed 's/end.state/nodump.state/; s/end.xyz/nodump.xyz/' > nodump.mote
run nodump.mote
cmp -s end.state nodump.state && ok || bad "a dump changed the run"

# 2D periodic box and 3D FCC crystal: snapshots of the perfect lattices, then of fluids
cat > lattice.mote <<'S'
bulk 108 0.50
snapshot fcc.xyz
save fcc.state
S
run lattice.mote
cat > disks.mote <<'S'
bulk_disks 100 0.60
snapshot hex.xyz
dump 5 disks.xyz
step 5
save disks.state
S
run disks.mote
cat > fluid.mote <<'S'
seed 2
bulk 500 0.40
step 200
snapshot fluid.xyz
S
run fluid.mote

# a mixing-box snapshot, which ASE must read too (species are element symbols)
printf 'model mixing-box\ndisks 30 20\nplace\nrun 0.1\nsnapshot mb.xyz\nsave mb.state\n' > mb.mote
run mb.mote

cat > check.py <<'S'
import sys
import numpy as np
import ase.io

failures = []
passes = 0

def check(cond, what):
    global passes
    if cond:
        passes += 1
    else:
        failures.append(what)

def state(path):
    """positions, velocities, radii, box, time, collisions of a mote state file"""
    lines = open(path).read().split("\n")
    head = {}
    i = 0
    while not lines[i].startswith("particles"):
        k, _, v = lines[i].partition(" ")
        head[k] = v
        i += 1
    dim = int(head["dim"])
    n = int(head["n"])
    rows = np.array([[float(x) for x in l.split()] for l in lines[i + 1:i + 1 + n]])
    pos = np.zeros((n, 3))
    vel = np.zeros((n, 3))
    pos[:, :dim] = rows[:, :dim]
    vel[:, :dim] = rows[:, dim:2 * dim]
    return dict(pos=pos, vel=vel, rad=rows[:, 2 * dim], box=[float(x) for x in head["box"].split()],
                time=float(head["time"]), coll=int(head["collisions"]), dim=dim,
                geometry=head["geometry"])

def same_as_state(atoms, st, what):
    check(len(atoms) == len(st["pos"]), what + ": N")
    check(np.array_equal(atoms.positions, st["pos"]), what + ": positions differ from the state")
    check(np.array_equal(atoms.arrays["velo"], st["vel"]), what + ": velocities differ")
    check(np.array_equal(atoms.arrays["radius"], st["rad"]), what + ": radii differ")
    cell = np.diag(atoms.cell)
    check(np.array_equal(cell[:st["dim"]], st["box"][:st["dim"]]), what + ": Lattice is not the box")
    pbc = list(atoms.pbc)
    want = [st["geometry"] == "periodic"] + [True] * (st["dim"] - 1) + [False] * (3 - st["dim"])
    check(pbc == want, what + ": pbc %s, expected %s" % (pbc, want))
    check(atoms.info["Time"] == st["time"], what + ": Time %r vs %r" % (atoms.info["Time"], st["time"]))
    check(atoms.info["collisions"] == st["coll"], what + ": collisions")
    check(set(atoms.get_chemical_symbols()) == {"X"}, what + ": species")

# the slit trajectory: frames at 0, 3 (= the state s1) and every 3 collisions per particle
frames = ase.io.read("traj.xyz", index=":", format="extxyz")
s0, s1, end = state("s0.state"), state("s1.state"), state("end.state")
n = len(s0["pos"])
colls = [f.info["collisions"] for f in frames]
check(colls[:2] == [0, 3 * n // 2], "trajectory frames at %s" % colls[:3])
check(all(b - a == 3 * n // 2 for a, b in zip(colls, colls[1:])), "frame spacing %s" % colls)
check(colls[-1] <= end["coll"] < colls[-1] + 3 * n // 2, "last frame %d, end %d" % (colls[-1], end["coll"]))
same_as_state(frames[0], s0, "dump frame 0")
same_as_state(frames[1], s1, "dump frame 1")
check(all("q6" in f.arrays and "solid" in f.arrays for f in frames), "q6 and solid columns")
check(all(np.diag(f.cell)[0] <= s0["box"][0] for f in frames), "the compression shows in Lattice")
same_as_state(ase.io.read("end.xyz", format="extxyz"), end, "snapshot")

# a perfect FCC lattice: q6 = 0.57452 (12 neighbours of FCC), every particle crystal-like
fcc = ase.io.read("fcc.xyz", format="extxyz")
same_as_state(fcc, state("fcc.state"), "fcc snapshot")
check(np.allclose(fcc.arrays["q6"], 0.57452, atol=2e-5), "FCC q6: %s" % fcc.arrays["q6"][:4])
check(fcc.arrays["solid"].min() == 1, "FCC: every particle solid")

# a hexagonal disk lattice: |psi6| = 1, every disk ordered; the trajectory ends at the state
hexa = ase.io.read("hex.xyz", format="extxyz")
check(np.allclose(hexa.arrays["psi6"], 1, atol=1e-5), "hex psi6: %s" % hexa.arrays["psi6"][:4])
check(hexa.arrays["ordered"].min() == 1, "hex: every disk ordered")
check(np.all(hexa.positions[:, 2] == 0), "disks at z = 0")
dframes = ase.io.read("disks.xyz", index=":", format="extxyz")
check(len(dframes) == 2, "disk dump frames: %d" % len(dframes))
same_as_state(dframes[-1], state("disks.state"), "disk dump last frame")

# a fluid at eta = 0.40 (far below freezing): almost no solid particle, q6 near 0.3-0.4
fl = ase.io.read("fluid.xyz", format="extxyz")
frac = fl.arrays["solid"].mean()
check(frac < 0.05, "fluid: solid fraction %.3f" % frac)
check(0.25 < fl.arrays["q6"].mean() < 0.5, "fluid: mean q6 %.3f" % fl.arrays["q6"].mean())

# the mixing box: He for colour 0, Ar for colour 1, positions as the state file has them
mb = ase.io.read("mb.xyz", format="extxyz")
lines = open("mb.state").read().split("\n")
k = lines.index("disks x y vx vy colour side t_last")
rows = [l.split() for l in lines[k + 1:k + 51]]
check(len(mb) == 50, "mixing box N")
check([s == ("Ar" if int(r[4]) else "He") for s, r in zip(mb.get_chemical_symbols(), rows)] == [True] * 50,
      "mixing box species follow the colours")
check(np.array_equal(mb.arrays["colour"], [int(r[4]) for r in rows]), "mixing box colour column")
check(np.array_equal(mb.positions[:, 0], [float(r[0]) for r in rows]),
      "mixing box x differs from the state")

for f in failures:
    print("FAILED:", f)
print("python checks: %d passed, %d failed" % (passes, len(failures)))
sys.exit(1 if failures else 0)
S
$PY check.py > py.txt 2>&1
st=$?
cat py.txt
p=$(sed -n 's/^python checks: \([0-9]*\) passed.*/\1/p' py.txt)
f=$(sed -n 's/^python checks: [0-9]* passed, \([0-9]*\) failed/\1/p' py.txt)
passed=$((passed + ${p:-0}))
failed=$((failed + ${f:-0}))
[ "$st" -eq 0 ] && ok || bad "check.py exited with $st"

# bad names and arguments are refused before anything runs
expect 1 "b1.mote:2:10: error: snapshot: FILE must end in .xyz (extended XYZ), .h5 (H5MD) or .vtk (VTK), found 'x.png'" \
    b1.mote "new 2 0.3\nsnapshot x.png\n"
expect 1 "b2.mote:2:6: error: trajectory: every must be >= 1, found 0" b2.mote "new 2 0.3\ndump 0 t.xyz\n"
expect 1 "b3.mote:1:1: error: snapshot: no system exists yet" b3.mote "snapshot x.xyz\n"
expect 1 "b4.mote:2:16: error: dump: too many arguments: expected 'trajectory every=K|dt=T file=FILE.xyz|FILE.h5 [format=xyz|h5md]' (bare values fill every=, file= in this order, unless given as key=value), found 't.xyz' left over" \
    b4.mote "new 2 0.3\ndump every=2 3 t.xyz\n"
expect 1 "b5.mote:2:8: error: dump: too many arguments" b5.mote "new 2 0.3\ndump 2 t.xyz every=3\n"

# the key=value forms (one vocabulary, issue 34), the alias trajectory, and both forms mixed
printf 'new 2 0.3\nsnapshot file=k1.xyz\ntrajectory every=1 file=k2.xyz\nstep 2\ndump file=k3.xyz 2\n' > k.mote
if "$MOTE" run k.mote > k.out 2>&1; then ok; else bad "k.mote: $(cat k.out)"; fi
[ "$(grep -c Lattice k1.xyz)" = 1 ] && ok || bad "snapshot file=: $(grep -c Lattice k1.xyz) frames"
[ "$(grep -c Lattice k2.xyz)" = 3 ] && ok || bad "trajectory every=1 over step 2: $(grep -c Lattice k2.xyz) frames, not 3"
grep -q "^trajectory: frame 0 in .*k3.xyz, then one every 2 collisions per particle" k.out && ok ||
    bad "dump file=k3.xyz 2: $(tail -1 k.out)"

mote_test_end
