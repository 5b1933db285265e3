#!/bin/sh
# test_h5md.sh: the H5MD trajectories and snapshots (format=h5md, or a .h5/.h5md name) of the
# four particle models, read back by h5py (Debian's python3-h5py, installed by
# scripts/setup.sh): the layout (h5md version, creator, box dimension and boundary, the units
# of the SI models), the shapes ([frames][N][D]), and every frame's numbers against the extended
# XYZ (or, for N-body, the table) that the same script writes in the other format: positions,
# velocities, radii or diameters, species, ids, time, step and box, to the last bit where the
# other file prints 17 digits. Also: a series of snapshots, a count of particles that grows
# (the separator's feed: rows past a frame's N are NaN and id -1), the same file byte for byte
# from the same run, a run stopped by SIGINT (at a safe point) keeps whole frames, and format=
# and a file's name must agree. (Python's Ctrl-C: tests/python/test_notebook.py; failed
# appends: tests/test_files.c.)
# Usage: sh tests/test_h5md.sh BUILD_DIR
NAME=test_h5md
ROOT=$(cd "$(dirname "$0")/.." && pwd)
. "$ROOT/tests/lib.sh"
mote_test_start "$1"
PY=/usr/bin/python3
if ! $PY -c 'import h5py, ase.io' 2>/dev/null; then
    bad "h5py or ASE is missing: run scripts/setup.sh test (python3-h5py, python3-ase)"
    mote_test_end
    exit 1
fi

run() { "$MOTE" run "$1" > out.txt 2> err.txt && ok || bad "$1: $(cat err.txt)"; }
# both SCRIPT: the script as written (H5MD) and with .h5 replaced by .xyz (XYZ)
both() {
    run "$1"
    sed 's/\.h5\b/.xyz/g; s/ format=h5md//' "$1" > "x_$1"
    run "x_$1"
}

cat > check.py <<'P'
import sys, h5py, numpy as np, ase.io

def fail(msg):
    print("FAILED:", msg)
    sys.exit(1)

def layout(f, model, dim, units):
    if list(f["h5md"].attrs["version"]) != [1, 1]:
        fail("h5md version")
    if f["h5md/creator"].attrs["name"] != b"mote" or "name" not in f["h5md/author"].attrs:
        fail("creator/author")
    if f["parameters/mote"].attrs["model"] != model.encode():
        fail("model %r" % f["parameters/mote"].attrs["model"])
    box = f["particles/all/box"]
    if box.attrs["dimension"] != dim or len(box.attrs["boundary"]) != dim:
        fail("box dimension/boundary %r" % dict(box.attrs))
    pos = f["particles/all/position"]
    if pos["value"].ndim != 3 or pos["value"].shape[2] != dim:
        fail("position shape %r" % (pos["value"].shape,))
    F = pos["value"].shape[0]
    if pos["step"].shape != (F,) or pos["time"].shape != (F,):
        fail("step/time shapes")
    if np.any(np.diff(pos["step"][:]) < 0) or np.any(np.diff(pos["time"][:]) < 0):
        fail("step or time goes back")
    if units:
        for name, unit in (("position", b"m"), ("velocity", b"m s-1")):
            if name in f["particles/all"] and f["particles/all/" + name + "/value"].attrs.get("unit") != unit:
                fail("%s unit %r" % (name, f["particles/all/" + name + "/value"].attrs.get("unit")))
        if pos["time"].attrs.get("unit") != b"s":
            fail("time unit")
    elif "unit" in pos["value"].attrs:
        fail("a unit on reduced units")
    return F

def exact(a, b, what, rtol=0.0):
    a, b = np.asarray(a, float), np.asarray(b, float)
    if a.shape != b.shape:
        fail("%s: shapes %r and %r" % (what, a.shape, b.shape))
    if rtol == 0.0 and not np.array_equal(a, b):
        fail("%s differ: %r vs %r" % (what, a.ravel()[:4], b.ravel()[:4]))
    if rtol and not np.allclose(a, b, rtol=rtol, atol=0):
        fail("%s differ beyond %g" % (what, rtol))

def against_xyz(h5, xyz, model, dim, units, scalar, rtol=0.0, order=None, planes=None):
    f = h5py.File(h5, "r")
    F = layout(f, model, dim, units)
    frames = ase.io.read(xyz, index=":")
    if len(frames) != F:
        fail("%s: %d frames, %s has %d" % (h5, F, xyz, len(frames)))
    a = f["particles/all"]
    ax = planes or list(range(dim))
    for k, fr in enumerate(frames):
        n = len(fr)
        exact(a["position/value"][k, :n], fr.positions[:, ax], "%s frame %d positions" % (h5, k), rtol)
        exact(a["velocity/value"][k, :n], fr.arrays["velo"][:, ax],
              "%s frame %d velocities" % (h5, k), rtol)
        exact(a[scalar[0] + "/value"][k, :n], fr.arrays["radius"] * scalar[1], "%s frame %d %s" % (h5, k, scalar[0]), rtol)
        if abs(a["position/time"][k] - fr.info["Time"]) > rtol * abs(fr.info["Time"]):
            fail("%s frame %d time %r vs %r" % (h5, k, a["position/time"][k], fr.info["Time"]))
        if "box/edges" in a:
            cell = np.diag(np.asarray(fr.cell[:]))[ax]
            exact(a["box/edges/value"][k], cell, "%s frame %d box" % (h5, k), rtol)
            b = [x.decode() for x in a["box"].attrs["boundary"]]
            if b != ["periodic" if p else "none" for p in np.asarray(fr.pbc)[ax]]:
                fail("%s boundary %r vs pbc %r" % (h5, b, fr.pbc))
        if order:
            exact(a[order + "/value"][k, :n], fr.arrays[order], "%s frame %d %s" % (h5, k, order), 1e-5)
        if "id/value" in a:
            exact(a["id/value"][k, :n], fr.arrays["id"], "%s frame %d id" % (h5, k))
            if a["id/value"].shape[1] > n and np.any(a["id/value"][k, n:] != -1):
                fail("%s frame %d: ids past N are not -1" % (h5, k))
            if a["position/value"].shape[1] > n and not np.all(np.isnan(a["position/value"][k, n:])):
                fail("%s frame %d: positions past N are not NaN" % (h5, k))
    return f

what = sys.argv[1]
if what == "hs":
    f = against_xyz("slit.h5", "slit.xyz", "hard-spheres", 3, False, ("radius", 1), order="q6")
    st = f["particles/all/position/step"][:]
    if not (len(st) >= 4 and st[0] == 0):
        fail("hs steps %r" % st)
    e = f["particles/all/box/edges/value"][:]
    if not e[-1, 0] < e[0, 0]:
        fail("the compression does not show in the box: %r" % e[:, 0])
    against_xyz("disks.h5", "disks.xyz", "hard-spheres", 2, False, ("radius", 1), order="psi6")
    against_xyz("snap.h5", "snap.xyz", "hard-spheres", 3, False, ("radius", 1))
elif what == "mb":
    f = against_xyz("mb.h5", "mb.xyz", "mixing-box", 2, True, ("radius", 1))
    fr = ase.io.read("mb.xyz", index=":")
    for k in range(len(fr)):
        exact(f["particles/all/species/value"][k], fr[k].arrays["colour"], "mb species")
    if f["particles/all/radius/value"].attrs.get("unit") != b"m":
        fail("mb radius unit")
    if list(f["h5md/modules/units"].attrs["version"]) != [1, 0]:
        fail("mb units module")
elif what == "sep":
    # 2D: the plane x, z (XYZ columns 0 and 2); diameter = 2 radius; ASE reads the XYZ (the
    # element X, the species' names in their own column)
    f = against_xyz("sep.h5", "sep.xyz", "separator", 2, True, ("diameter", 2), planes=[0, 2])
    a = f["particles/all"]
    last = ase.io.read("sep.xyz", index=-1)
    names = ["quartz", "ore"]
    if set(last.get_chemical_symbols()) != {"X"} or \
            list(last.arrays["species_name"]) != [names[k] for k in a["species/value"][-1, :len(last)]]:
        fail("the XYZ's species: %r" % (sorted(set(last.arrays["species_name"])),))
    n = [int(np.sum(a["id/value"][k] >= 0)) for k in range(a["id/value"].shape[0])]
    if not (n[0] == 0 and n[-1] > n[1] > 0):
        fail("the separator's count does not grow: %r" % n)
    if [x.decode() for x in a["species"].attrs["names"]] != ["quartz", "ore"]:
        fail("species names %r" % a["species"].attrs["names"])
    if a["diameter/value"].attrs.get("unit") != b"m":
        fail("diameter unit")
elif what == "vtk":
    # VTK snapshots (legacy binary, read by VTK itself) against the H5MD ones of the same
    # moment, in the three models that write them: the same numbers to the last bit under the
    # same names; 2D positions and vectors with z = 0
    from vtkmodules.vtkIOLegacy import vtkPolyDataReader
    from vtkmodules.util.numpy_support import vtk_to_numpy as v2n
    def vtk(path):
        r = vtkPolyDataReader()
        r.SetFileName(path)
        r.ReadAllScalarsOn()
        r.ReadAllVectorsOn()
        r.ReadAllFieldsOn()
        r.Update()
        return r.GetOutput()
    def same(vpath, hpath, names):
        d = vtk(vpath)
        a = h5py.File(hpath, "r")["particles/all"]
        n, pd = d.GetNumberOfPoints(), d.GetPointData()
        dim = a["position/value"].shape[2]
        if n != a["position/value"].shape[1] or n < 20 or d.GetNumberOfVerts() != n:
            fail("%s: %d points, %d vertices" % (vpath, n, d.GetNumberOfVerts()))
        got = sorted(pd.GetArrayName(k) for k in range(pd.GetNumberOfArrays()))
        if got != sorted(names):
            fail("%s: arrays %r" % (vpath, got))
        pts = v2n(d.GetPoints().GetData())
        exact(pts[:, :dim], a["position/value"][0], vpath + " positions")
        for name in names:
            v = v2n(pd.GetArray(name))
            h = a[name + "/value"][0]
            exact(v[:, :dim] if v.ndim == 2 else v, h, "%s %s" % (vpath, name))
            if v.ndim == 2 and dim == 2 and np.any(v[:, 2] != 0):
                fail("%s: a 2D frame's %s has z" % (vpath, name))
        if dim == 2 and np.any(pts[:, 2] != 0):
            fail("%s: a 2D frame's z is not 0" % vpath)
        fd = d.GetFieldData()
        if fd.GetArray("TIME").GetValue(0) != a["position/time"][0] or \
                fd.GetArray("STEP").GetValue(0) != a["position/step"][0]:
            fail("%s: time/step" % vpath)
        return d, a
    d, a = same("vnow.vtk", "vnow.h5", ["velocity", "species", "id", "diameter", "contact_force"])
    for dm in (3, 2):
        hd, ha = same("hz%dnow.vtk" % dm, "hz%dnow.h5" % dm,
                      ["velocity", "species", "id", "diameter", "contact_force", "angular_velocity"])
        if not (abs(ha["angular_velocity/value"][0]).max() > 1):
            fail("hz%d: no spin" % dm)
    F = v2n(d.GetPointData().GetArray("contact_force"))
    if np.count_nonzero(np.abs(F).sum(axis=1)) < 2:
        fail("VTK: no particle is in contact")
    if a["contact_force/value"].attrs.get("unit") != b"N":
        fail("contact force unit")
    same("hsnow.vtk", "hsnow.h5", ["velocity", "radius", "q6"])
    same("mbnow.vtk", "mbnow.h5", ["velocity", "species", "radius"])
    # series on a schedule: one file per snapshot, times increasing
    for pre, k in (("vs/p", 3), ("hs_vs/p", 3), ("mb_vs/p", 3)):
        times = [vtk("%s_%06d.vtk" % (pre, j)).GetFieldData().GetArray("TIME").GetValue(0) for j in range(k)]
        if not times[0] < times[1] < times[2]:
            fail("%s: VTK series times %r" % (pre, times))
elif what == "nbody":
    f = h5py.File("nb.h5", "r")
    F = layout(f, "nbody", 3, False)
    t = np.loadtxt("nb.traj", comments="#")
    cols = open("nb.traj").read().split("# columns:")[1].split("\n")[0].split()
    if t.shape[0] != F:
        fail("nbody: %d frames, the table has %d rows" % (F, t.shape[0]))
    a = f["particles/all"]
    exact(a["position/time"][:], t[:, cols.index("T")], "nbody time")
    for b in range(3):
        for ax, c in enumerate("xyz"):
            exact(a["position/value"][:, b, ax], t[:, cols.index("%s%d" % (c, b + 1))], "nbody %s%d" % (c, b + 1))
            exact(a["velocity/value"][:, b, ax], t[:, cols.index("v%s%d" % (c, b + 1))], "nbody v%s%d" % (c, b + 1))
    exact(a["mass/value"][0], [1.0, 1e-3, 1e-3], "nbody masses")
    exact(a["id/value"][0], [0, 1, 2], "nbody ids")
    if "box/edges" in a or [x.decode() for x in a["box"].attrs["boundary"]] != ["none"] * 3:
        fail("nbody box")
    g = h5py.File("si.h5", "r")
    layout(g, "nbody", 3, True)
    m = g["particles/all/mass/value"]
    if m.attrs.get("unit") != b"kg" or not 1.98e30 < m[0, 0] < 2.0e30:
        fail("solar masses in kg: %r" % m[0, 0])
    r = np.linalg.norm(g["particles/all/position/value"][0, 1] - g["particles/all/position/value"][0, 0])
    if not 4.9 < r / 1.495978707e11 < 5.5:
        fail("Jupiter's distance from the Sun: %g au" % (r / 1.495978707e11))
elif what == "stopped":
    f = h5py.File("stop.h5", "r")
    F = layout(f, "hard-spheres", 3, False)
    p = f["particles/all/position/value"][:]
    if F < 5 or np.isnan(p).any():
        fail("the stopped run's trajectory: %d frames, NaN %s" % (F, np.isnan(p).any()))
elif what == "series":
    for k in range(3):
        f = h5py.File("ser/p_%06d.h5" % k, "r")
        if layout(f, "hard-spheres", 3, False) != 1:
            fail("a snapshot of the series is not one frame")
else:
    fail("no check " + what)
print("ok")
P
check() { out=$($PY check.py "$1" 2>&1) && [ "$out" = ok ] && ok || bad "$1: $out"; }

# hard spheres: a 3D slit across steps and a compression (the box shrinks), a 2D periodic
# trajectory, a snapshot; each written again as extended XYZ
cat > hs.mote <<'S'
seed 5
new 3 0.40
trajectory 2 slit.h5
step 3
compress_left_wall 0.43 0.05 1
step 2
snapshot snap.h5
bulk_disks 100 0.60
trajectory every=2 file=disks.h5 format=h5md
step 5
S
both hs.mote
check hs

# the mixing box (SI units, colours as species)
MB='model mixing-box\nseed 5\nbox 0 0.4 0 0.2\npartition 0.2 0.01\nslit 0.1 0.04\nradius 0.004\ndisks 30 20\nv_init 1\nplace\n'
printf '%btrajectory dt=0.05 file=mb.h5\nrun 0.3\n' "$MB" > mb.mote
both mb.mote
check mb

# the separator: fed from empty (N grows), two species
printf '%bspecies ore 4500\nsize ore lognormal d50=120e-6 sigma=1.6 min=30e-6 max=600e-6\nfeed_fraction quartz 0.7\nfeed_fraction ore 0.3\ntrajectory dt=0.05 file=sep.h5\nrun 0.2\n' "$SEP_DILUTE" > sep.mote
both sep.mote
check sep

# a VTK snapshot (format=vtk, or a .vtk name) holds what the H5MD snapshot of the same moment
# holds, contact forces included (a bed on a plate, soft-sphere contacts); and a series
cat > vt.mote <<'S'
model separator
seed 4
channel 0.06 0.4
gas 12
species ore 3500
size ore lognormal d50=4e-3 sigma=1.2 min=3e-3 max=5e-3
species coke 900
size coke lognormal d50=4e-3 sigma=1.2 min=3e-3 max=5e-3
feed_fraction ore 0.5
feed_fraction coke 0.5
feed z=0.12 rate=0.1
grid 0.1 0.004 pattern a=4.5e-3 p=9e-3 offset=0
stiffness overlap=0.1 vimp=12
run 0.08
snapshot file=vnow.h5
snapshot file=vnow.vtk
snapshot every=1000 prefix=vs/p format=vtk
run 0.002
S
run vt.mote
# contact hertz: the angular velocity too (3D: a vector; 2D: about y)
for dm in 3 2; do
    [ $dm = 3 ] && ch='channel 0.02 0.04 D=0.02' || ch='channel 0.02 0.04'
    printf 'model separator\nseed 5\ndim %s\n%s\nends closed closed\ngas 0 rho=0 mu=0\nspecies name=glass density=2500 E=5e6 nu=0.3\nsize glass mono d=2e-3\nfeed z=0.02 hf=0.03\ncontact hertz\nfriction 0.5\ninsert glass 60\nrun 0.08\nsnapshot file=hz%snow.h5\nsnapshot file=hz%snow.vtk\n' $dm "$ch" $dm $dm > hz$dm.mote
    run hz$dm.mote
done
printf 'seed 2\nnew 3 0.40\nstep 1\nsnapshot file=hsnow.h5\nsnapshot file=hsnow.vtk\nsnapshot every=1 prefix=hs_vs/p format=vtk\nstep 2\n' > hsv.mote
run hsv.mote
printf '%brun 0.05\nsnapshot file=mbnow.h5\nsnapshot file=mbnow.vtk\nsnapshot dt=0.01 prefix=mb_vs/p format=vtk\nrun 0.03\n' "$MB" > mbv.mote
run mbv.mote
check vtk
expect 1 "v1.mote:9:25: error: trajectory: a VTK file holds one frame: write a series with snapshot every=K prefix=P format=vtk (or a trajectory .xyz or .h5)" v1.mote "${SEP_DILUTE}trajectory every=1 file=t.vtk\n"
expect 1 "v2.mote:3:25: error: trajectory: a VTK file holds one frame: write a series with snapshot every=K prefix=P format=vtk (or a trajectory .xyz or .h5)" v2.mote 'seed 1\nnew 3 0.40\ntrajectory every=1 file=t.vtk\n'
expect 1 "v5.mote:10:25: error: trajectory: a VTK file holds one frame: write a series with snapshot every=K prefix=P format=vtk (or a trajectory .xyz or .h5)" v5.mote "${MB}trajectory every=1 file=t.vtk\n"
# (the separator's `snapshots`, the other name of `snapshot`, takes VTK as snapshot does)
expect 1 "v6.mote:10:25: error: trajectory: a VTK file holds one frame" v6.mote "${SEP_DILUTE}snapshots every=5 prefix=p format=vtk\ntrajectory every=1 file=t.vtk\n"
expect 1 "v3.mote:3:15: error: snapshot: format=vtk writes VTK: name the file FILE.vtk" v3.mote 'seed 1\nnew 3 0.40\nsnapshot file=t.xyz format=vtk\n'
expect 1 "v4.mote:10:15: error: snapshot: a file named .vtk is VTK: give format=vtk or another name" v4.mote "${MB}snapshot file=t.vtk format=h5md\n"

# N-body: dimensionless (no scales) against the table, velocities on; the Sun and Jupiter in
# SI from the solar-system generator's scales
cat > nb.mote <<'S'
model nbody gravity
body mass=1
body mass=1e-3 x=1 vy=1
body mass=1e-3 x=-2 vy=-0.7
trajectory every=10 file=nb.traj velocities=on
integrate steps=50
S
run nb.mote
sed 's/file=nb.traj/file=nb.h5/' nb.mote > nb5.mote
run nb5.mote
SOLAR="model nbody gravity\ngenerate solar_system data=$ROOT/data/outer_solar_system.dat\n"
printf '%btrajectory every=1 file=si.h5\n' "$SOLAR" > si.mote
run si.mote
check nbody

# a series of snapshots, one frame each
printf 'seed 2\nnew 3 0.40\nsnapshot every=1 prefix=ser/p format=h5md\nstep 2\n' > ser.mote
run ser.mote
check series

# the same run writes the same file, byte for byte (no times in it)
cp slit.h5 slit.first
run hs.mote
cmp -s slit.h5 slit.first && ok || bad "the same run wrote a different slit.h5"

# stopped with SIGINT after a few frames (the monitor's rows say how far it is): mote run stops
# the command at a safe point, so the frames written so far are there and whole
printf 'seed 3\nbulk 500 0.30\ntrajectory every=1 file=stop.h5\nmonitor every=1 file=stop.dat\nstep 100000\n' > stop.mote
sigint_after_rows stop.mote stop.dat.partial 6 stop.out
[ "$sigint_rc" -eq 130 ] && grep -q "stop.mote:5:1: error: step: interrupted; it stopped at a safe point" stop.out &&
    grep -q "^mote: stopped by Ctrl-C (SIGINT)" stop.out && ok || bad "the run was not stopped at a safe point by SIGINT ($sigint_rc): $(cat stop.out)"
check stopped

# format= and the name must agree; a trajectory's name says what it is
expect 1 "f1.mote:3:25: error: trajectory: format=h5md writes H5MD: name the file FILE.h5 or FILE.h5md" f1.mote 'seed 1\nnew 3 0.40\ntrajectory every=1 file=t.xyz format=h5md\n'
expect 1 "f2.mote:3:15: error: snapshot: a file named .h5 or .h5md is H5MD: give format=h5md or another name" f2.mote 'seed 1\nnew 3 0.40\nsnapshot file=t.h5 format=xyz\n'
expect 1 "f3.mote:3:25: error: trajectory: FILE must end in .xyz (extended XYZ) or .h5 (H5MD), found 't.dat'" f3.mote 'seed 1\nnew 3 0.40\ntrajectory every=1 file=t.dat\n'
expect 1 "f4.mote:3:35: error: trajectory: unit= names the table's time column; an H5MD file carries SI units (seconds) when the run has physical scales" f4.mote "${SOLAR}trajectory every=1 file=t.h5 unit=day\n"
printf '%bsnapshot file=m.png format=xyz\n' "$MB" > f5.mote
"$MOTE" run f5.mote > out.txt 2> err.txt
grep -q "snapshot: format= is for the particle files (.xyz, .h5, .vtk); a .png is a picture" err.txt && ok || bad "f5: $(cat err.txt)"

mote_test_end
