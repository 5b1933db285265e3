"""The Python package against the program: the same lines give the same bits, errors are
MoteError with mote's message and run nothing, arrays and views, setters that check, data files,
progress, the GIL."""
import os
import re
import subprocess
import threading

import numpy as np
import pytest

import mote

TIMING = re.compile(r"(seconds|collisions_per_second|wall_seconds|cpu_s|wall_s)=\S+")


def untimed(text):
    return [TIMING.sub("", l) for l in text.splitlines() if "traces/s" not in l]


def test_models_and_version():
    assert mote.models() == ["hard-spheres", "mixing-box", "nbody", "charging", "separator"]
    assert re.match(r"^\d+\.\d+\.\d+$", mote.__version__)


def test_run_is_the_program(tmp_path, mote_bin, monkeypatch):
    """mote.run of a script and `mote run` of the same file: the same output and files."""
    script = ("seed 3\nnew 2 0.3\nstep 40\npressure 20 p.dat\nimage 10 4 rho.dat\n"
              "save s.state\n")
    for d in ("cli", "py"):
        (tmp_path / d).mkdir()
        (tmp_path / d / "s.mote").write_text(script)
    cli = subprocess.run([mote_bin, "run", "s.mote"], cwd=tmp_path / "cli",
                         capture_output=True, text=True, check=True).stdout
    monkeypatch.chdir(tmp_path / "py")
    py = mote.run_file("s.mote")
    assert untimed(py) == untimed(cli)
    for f in ("p.dat", "rho.dat", "s.state"):
        a = (tmp_path / "cli" / f).read_bytes()
        b = (tmp_path / "py" / f).read_bytes()
        # the data files name their command's script: the same name in both
        assert a == b, f


def test_simulation_is_the_script(tmp_path, mote_bin):
    """Commands one by one from Python and the same lines as a script: the same state, bit for
    bit (the nbody ring, then hard spheres with random numbers)."""
    lines = ["generate ring nb=30", "integrator galactica dt=1e-6", "integrate steps=300",
             "integrator taylor order=12 tol=1e-16", "integrate steps=7",
             "save %s" % (tmp_path / "py.state")]
    sim = mote.Simulation("nbody gravity")
    for l in lines:
        sim.command(l)
    script = "model nbody gravity\n" + "\n".join(lines).replace("py.state", "cli.state") + "\n"
    (tmp_path / "r.mote").write_text(script)
    subprocess.run([mote_bin, "run", "r.mote"], cwd=tmp_path, check=True, capture_output=True)
    assert (tmp_path / "py.state").read_bytes() == (tmp_path / "cli.state").read_bytes()
    hs = mote.Simulation()
    hs.command("seed 9\nnew 3 0.35")
    hs.command("step 30")
    hs.command("save %s" % (tmp_path / "hp.state"))
    (tmp_path / "h.mote").write_text("seed 9\nnew 3 0.35\nstep 30\nsave hc.state\n")
    subprocess.run([mote_bin, "run", "h.mote"], cwd=tmp_path, check=True, capture_output=True)
    assert (tmp_path / "hp.state").read_bytes() == (tmp_path / "hc.state").read_bytes()


def test_parameters():
    out = mote.run("echo eta=${eta} twice=${2*eta}\n", eta=0.3)
    assert out == "eta=0.3 twice=0.6\n"


def test_errors_name_the_line_and_run_nothing(tmp_path):
    f = tmp_path / "never.dat"
    with pytest.raises(mote.MoteError) as e:
        mote.run("new 2 0.3\nimage 10 4 %s\nstep nope\n" % f, name="s.mote")
    assert str(e.value) == "s.mote:3:6: error: step: expected an integer for K, found 'nope'"
    assert not f.exists()
    with pytest.raises(mote.MoteError, match=r"undefined variable 'eta'"):
        mote.run("new 2 ${eta}\n")
    with pytest.raises(mote.MoteError, match=r"this loop has no 'end'"):
        mote.run("for a in 1 2\necho ${a}\n")
    with pytest.raises(mote.MoteError, match=r"not a number"):
        mote.run("echo ${1+x}\n", x="abc")
    with pytest.raises(mote.MoteError, match=r"parameter 'eta' is given twice|given twice"):
        mote._mote.run("echo ${eta}\n", "<p>", ["eta=1", "eta=2"])


def test_simulation_errors_leave_the_state():
    sim = mote.Simulation("hard-spheres")
    sim.command("new 2 0.3")
    before = sim.status_line()
    with pytest.raises(mote.MoteError, match=r"^<python>:3:6: error: step: expected"):
        sim.command("step -4")
    assert sim.status_line() == before
    with pytest.raises(mote.MoteError, match=r"only one 'model' command is allowed"):
        sim.command("model nbody")
    with pytest.raises(mote.MoteError, match=r"unknown model"):
        mote.Simulation("nosuch")
    sim.command("step 5")  # (still usable)
    assert sim.status()["collisions"] == 5 * 64 // 2  # (K collisions per sphere, two per pair)


def test_status_and_arrays():
    sim = mote.Simulation("hard-spheres")
    sim.command("new 2 0.3")
    st = sim.status()
    assert st["N"] == 64 and st["eta"] == 0.3 and st["geometry"] == "slit"
    x, r = sim.positions, sim.radii
    assert x.shape == (64, 3) and r.shape == (64,) and np.all(r == 1.0)
    assert np.all(x[:, 0] >= 1.0) and np.all(x[:, 0] <= st["L"] - 1.0)  # between the walls
    x[0, 0] = -5  # a copy: the model is untouched
    assert sim.positions[0, 0] != -5
    atoms = sim.to_ase()
    assert np.allclose(atoms.get_positions(), sim.positions)
    assert list(atoms.get_pbc()) == [False, True, True]
    assert np.allclose(atoms.cell.lengths(), [st["L"], st["A"], st["A"]])


def test_to_ase_by_the_arrays():
    # to_ase follows the model's arrays (particles with radii), not a list of model names
    sim = mote.Simulation("mixing-box")
    sim.command("disks 10 10")
    sim.command("place")
    atoms = sim.to_ase()
    assert len(atoms) == 20 and np.allclose(atoms.get_array("radius"), sim.radii)
    # the cell is the model's box, as its XYZ files' Lattice: the mixing box's walls (corner at
    # x_l, x_b), the separator's channel W x D x H (2D: the nominal depth), no periodic axis
    assert list(atoms.cell.lengths()) == [2.0, 1.0, 0.0] and not any(atoms.pbc)  # the default box
    box = mote.MixingBox(setup="box 0.1 0.5 -0.2 0.3\npartition 0.3 0.01\nslit 0.05 0.04\n"
                               "radius 0.004\ndisks 5 5\nplace")
    a = box.to_ase()
    assert list(a.cell.lengths()) == [0.4, 0.5, 0.0] and list(a.get_celldisp().ravel()) == [0.1, -0.2, 0.0]
    assert np.all(a.positions[:, 0] >= 0.1) and np.all(a.positions[:, 1] >= -0.2)
    sep = mote.Separator(setup="channel 0.05 1\ngas 1.5\ncollisions off\ntimestep 1e-3\n"
                               "species quartz 2650\nsize quartz mono d=1e-4\nfeed z=0.5 rate=2e-5")
    sep.run(0.05)
    a = sep.to_ase()
    assert len(a) > 0 and list(a.cell.lengths()) == [0.05, 1e-4, 1.0] and not any(a.pbc)
    sep3 = mote.Separator(setup="dim 3\nchannel 0.02 0.08 D=0.015\ngas 1.5\n"
                                "species glass 2500\nsize glass mono d=1e-3\nfeed z=0.04 rate=1e-3")
    assert list(sep3.to_ase().cell.lengths()) == [0.02, 0.015, 0.08]
    nb = mote.Simulation("nbody")
    nb.command("generate ring nb=4")
    with pytest.raises(mote.MoteError, match="not particles with radii"):
        nb.to_ase()


def test_views_and_setters():
    sim = mote.Simulation("nbody")
    sim.command("generate ring nb=12")
    v = sim.view("positions")
    assert not v.flags.writeable and np.array_equal(v, sim.positions)
    with pytest.raises(ValueError):
        v[0, 0] = 1.0
    with pytest.raises(mote.MoteError, match=r"view .* still held"):
        sim.command("integrate steps=1")
    row = v[1]  # a slice keeps the view alive
    del v
    with pytest.raises(mote.MoteError, match=r"still held"):
        sim.command("integrate steps=1")
    del row
    sim.command("integrate steps=1")
    x = sim.positions
    with pytest.raises(mote.MoteError, match=r"expected 12 x 3 numbers .* found 12 x 2"):
        sim.set("positions", x[:, :2])
    with pytest.raises(mote.MoteError, match=r"body 4: a finite number up to 1e100"):
        bad = x.copy()
        bad[3, 1] = np.nan
        sim.set("positions", bad)
    with pytest.raises(mote.MoteError, match=r"body 1: a finite number up to 1e100 .* found 1e\+300"):
        sim.set("velocities", np.full(x.shape, 1e300))  # (issue 52: the next command refused it)
    with pytest.raises(mote.MoteError, match=r"a mass is > 0 and up to 1e100"):
        sim.set("masses", -sim.masses)
    assert np.array_equal(sim.positions, x)  # refused: unchanged
    y = x * 1.01
    sim.set("positions", y)
    assert np.array_equal(sim.positions, y)
    assert sim.status()["dE"] == 0.0  # energies measured from the new state
    ch = mote.Simulation("charging")
    with pytest.raises(mote.MoteError, match=r"cannot be set"):
        ch.set("positions", [[0.0, 0.0, 0.0]])


def test_separator_setters():
    """The particles' positions and velocities set from Python: finite, centres inside the
    channel; the run goes on from them (the pair list built again)."""
    sp = mote.Simulation("separator")
    sp.command("channel 0.05 1\ngas 1.5\ncollisions off\ntimestep 1e-3\nspecies quartz 2650\n"
               "size quartz lognormal d50=150e-6 sigma=1.6 min=30e-6 max=600e-6\n"
               "feed z=0.5 rate=2e-5\ninsert quartz 50\nrun 0.01")
    x = sp.positions
    n = len(x)
    y = x.copy()
    y[:, 2] = 0.3  # every particle lifted to z = 0.3 m
    sp.set("positions", y)
    assert np.array_equal(sp.positions, y)
    bad = y.copy()
    bad[2, 2] = 2.0
    with pytest.raises(mote.MoteError, match=r"particle 2: z = 2 is outside the channel \[0, 1\]"):
        sp.set("positions", bad)
    with pytest.raises(mote.MoteError, match=r"expected %d x 3 numbers" % n):
        sp.set("velocities", np.zeros((n, 2)))
    with pytest.raises(mote.MoteError, match=r"particle 0: vx = 1e\+300 m/s is beyond 1e\+06 m/s"):
        sp.set("velocities", np.full((n, 3), 1e300))  # (it ran, then lost every particle)
    sp.set("velocities", np.zeros((n, 3)))
    assert np.array_equal(sp.velocities, np.zeros((n, 3)))
    sp.command("run 0.01")
    assert sp.status()["t"] > 0.01


def test_mixing_box_setters():
    """The disks' positions and velocities set from Python: checked as a state file is (centres
    in the box, speeds up to 1e6 m/s), their chambers following; the run goes on from them."""
    m = mote.Simulation("mixing-box")
    with pytest.raises(mote.MoteError, match=r"no disks yet"):
        m.set("positions", [[0.1, 0.1]])
    m.command("box 0 0.4 0 0.2\npartition 0.2 0.01\nslit 0.1 0.04\nradius 0.004\n"
              "disks 30 20\nv_init 1\nplace")
    x = m.positions
    y = x.copy()
    y[:, 0] = 0.4 - y[:, 0]  # mirrored: every disk in the other chamber
    m.set("positions", y)
    st = m.status()
    assert np.array_equal(m.positions, y) and st["m"] == 1 and st["nR0"] == 30
    with pytest.raises(mote.MoteError, match=r"disk 0: .* is outside the box"):
        m.set("positions", y + 1)
    with pytest.raises(mote.MoteError, match=r"above 10\^6 m/s"):
        m.set("velocities", np.full((50, 2), 2e6))
    with pytest.raises(mote.MoteError, match=r"expected 50 x 2 numbers"):
        m.set("velocities", np.zeros((50, 3)))
    m.set("velocities", 2 * m.velocities)
    m.command("run 0.1")
    assert m.status()["t"] == 0.1


def test_hard_sphere_setters():
    """Positions and velocities set from Python: checked (walls, overlaps, shape), exact, and
    the run goes on from them; a refused array leaves the system unchanged."""
    hs = mote.Simulation()
    hs.command("new 2 0.3\nstep 20")
    x = hs.positions
    hs.set("positions", x)
    assert np.array_equal(hs.positions, x)  # exactly what was set
    bad = x.copy()
    bad[1] = bad[0] + [0, 0.5, 0]
    with pytest.raises(mote.MoteError, match=r"particles 0 and 1 overlap: their distance is 0.25 of contact"):
        hs.set("positions", bad)
    bad = x.copy()
    bad[3, 0] = 0.5
    with pytest.raises(mote.MoteError, match=r"particle 3: x = 0.5 is outside the walls"):
        hs.set("positions", bad)
    with pytest.raises(mote.MoteError, match=r"expected 64 x 3 numbers"):
        hs.set("velocities", x[:10])
    with pytest.raises(mote.MoteError, match=r"particle 0: vx = 1e\+200 is not a finite number up to 1e100"):
        hs.set("velocities", np.full((64, 3), 1e200))  # (issue 52: what the next command refuses)
    assert np.array_equal(hs.positions, x)
    kT = hs.status()["kT"]
    hs.set("velocities", 2 * hs.velocities)
    assert abs(hs.status()["kT"] / kT - 4) < 1e-12
    hs.command("step 20")
    assert hs.status()["collisions"] == 2 * 20 * 64 // 2


def test_read_data(tmp_path):
    mote.run("output_dir %s\nensemble 2 file=e.dat\nbulk 32 0.3\nstep 50\npressure 50 p_${replica}.dat\nend\n"
             % tmp_path)
    d = mote.read_data(str(tmp_path / "e.dat"))
    assert d.format == "ensemble" and d.header["replicas"] == 2
    z = d.column("pressure.Z")
    mean, err = d.header["pressure.Z"]
    assert len(z) == 2 and abs(z.mean() - mean) <= 1e-9 * abs(mean)
    p = mote.read_data(str(tmp_path / "p_1.dat"))
    assert p.columns[0] == "x_mid[R]" and p.data.shape == (len(p.data), len(p.columns))
    with pytest.raises(KeyError):
        p.column("nosuch")
    (tmp_path / "x.dat").write_text("hello\n")
    with pytest.raises(mote.MoteError, match=r"x.dat:1: not a mote data file"):
        mote.read_data(str(tmp_path / "x.dat"))


def test_progress():
    seen = []
    mote.run("new 3 0.3\nstep 3000\n", progress=lambda label, f: seen.append((label, f)))
    assert seen and all(l == "step" and 0 <= f <= 1 for l, f in seen)
    fr = [f for _, f in seen]
    assert fr == sorted(fr)


def test_gil_released():
    """While one thread runs a long command, another runs Python: the run releases the GIL."""
    sim = mote.Simulation()
    sim.command("new 4 0.3")
    started, done = threading.Event(), threading.Event()
    seen_running = []

    def work():
        started.set()
        sim.command("step 2000")  # (about 0.3 s; the loop below needs 1000 rounds of it)
        done.set()

    t = threading.Thread(target=work)
    t.start()
    started.wait()
    # a thread holding the GIL for the whole command would let this line run only after it
    n = 0
    while not done.is_set() and n < 10**7:
        n += 1
        if n == 1000:
            seen_running.append(not done.is_set())
    t.join()
    assert seen_running == [True]


def test_close_while_running():
    """close() from another thread while a command runs is refused (it crashed: issue 52); the
    command finishes and the session closes after it."""
    sim = mote.Simulation()
    sim.command("new 4 0.3")
    running, results = threading.Event(), []

    def work():
        results.append(sim.command("step 3000", progress=lambda label, f: running.set()))

    t = threading.Thread(target=work)
    t.start()
    assert running.wait(120)  # the command's first progress report: it is under way
    with pytest.raises(mote.MoteError, match="running a command in another thread"):
        sim.close()
    t.join()
    assert results and sim.status()["collisions"] > 0
    sim.close()


def test_read_data_missing(tmp_path):
    """A file that is not there: mote's error naming it, as for every file mote reads."""
    with pytest.raises(mote.MoteError, match=r"nosuch\.dat: cannot open: No such file"):
        mote.read_data(str(tmp_path / "nosuch.dat"))


def test_byte_order_mark():
    """A script or a command that starts with a UTF-8 byte-order mark (as some editors save)."""
    assert "N=64" in mote.run("\ufeffnew 2 0.3\n")
    sim = mote.Simulation()
    sim.command("\ufeffnew 2 0.3")
    assert sim.status()["N"] == 64


def test_keyboard_interrupt(ctrl_c):
    """Ctrl-C during a long command (issue 52: it arrived only when the command had finished):
    the command stops at its next safe point, KeyboardInterrupt is raised, and the state is
    consistent: it runs on."""
    first_report, sent = ctrl_c()
    sim = mote.Simulation()
    sim.command("new 4 0.3")
    with pytest.raises(KeyboardInterrupt):
        sim.command("step 1000000", progress=first_report)  # minutes if not stopped
    done = sim.status()["collisions"]
    assert sent and 0 < done < 1000000 * 2000 // 2
    sim.command("step 10")
    assert sim.status()["collisions"] > done
    with pytest.raises(KeyboardInterrupt):  # the same for a whole script
        mote.run("new 4 0.3\nstep 1000000\n", progress=ctrl_c()[0])


def test_keyboard_interrupt_charging_and_ensembles(ctrl_c):
    """Ctrl-C stops a charging run (its threads at their next block) and an ensemble (every
    replica at its next safe point; the one on the script's thread asks Python): each command
    that would take minutes returns at once, and the simulation runs on."""
    import os
    import signal
    ch = mote.Simulation("charging")
    ch.command("plasma preset single n=1e6 kT=10\nbody sphere radius=1")
    with pytest.raises(KeyboardInterrupt):
        ch.command("run particles=1e12", progress=ctrl_c()[0])  # hours if not stopped
    printed = ch.command("run particles=1000")
    assert "run: net I = " in printed
    # an ensemble reports only as replicas end: Ctrl-C comes from a timer, as from a user
    import threading
    for script in ("ensemble 2\nnew 4 0.3\nstep 1000000\nend\n",  # two replicas, two threads
                   "threads 1\nensemble 3\nnew 4 0.3\nstep 1000000\nend\n"):  # one thread
        timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            mote.run(script)
        timer.join()


def test_separator_angular_velocities():
    """contact hertz: the angular velocities as an array (rad/s, rows of x y z), spinning after
    a pour with friction; absent with the linear law."""
    sim = mote.Simulation("separator")
    for line in ("dim 3", "channel 0.02 0.04 D=0.02", "ends closed closed", "gas 0 rho=0 mu=0",
                 "species name=glass density=2500 E=5e6 nu=0.3", "size glass mono d=2e-3",
                 "feed z=0.02 hf=0.03", "contact hertz", "friction 0.5", "insert glass 60",
                 "run 0.05"):
        sim.command(line)
    w = sim.arrays()["angular_velocities"]
    assert w.shape == (60, 3) and np.all(np.isfinite(w)) and np.abs(w).max() > 1
    assert sim.units()["angular_velocities"] == "rad/s"
    lin = mote.Simulation("separator")
    for line in ("channel 0.02 0.04", "gas 0", "species glass 2500", "size glass mono d=2e-3",
                 "feed z=0.02", "insert glass 5"):
        lin.command(line)
    assert "angular_velocities" not in lin.arrays()
