# What a notebook shows of a simulation (picture, status, progress) and the H5MD files read
# back with h5py (docs/python.md "Notebooks", docs/file-formats.md §5b).
import os

import numpy as np
import pytest

import mote

PNG = b"\x89PNG\r\n\x1a\n"


def png_size(data):
    """Width and height from a PNG's IHDR."""
    assert data[:8] == PNG
    return int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")


def test_picture_of_every_model_that_draws(tmp_path):
    sims = {
        "hard-spheres": mote.HardSpheres(N=500, eta=0.3),
        "nbody": mote.NBody(),
        "mixing-box": mote.Simulation("mixing-box"),
        "separator": mote.Simulation("separator"),
    }
    sims["nbody"].add(m=1)
    sims["nbody"].add(m=1e-3, a=1)
    sims["mixing-box"].command("box 0 0.4 0 0.2\npartition 0.2 0.01\nslit 0.1 0.04\n"
                               "radius 0.004\ndisks 30 20\nv_init 1\nplace")
    sims["separator"].command("channel 0.05 1\ngas 1.5\ncollisions off\ntimestep 1e-3\n"
                              "species quartz 2650\n"
                              "size quartz lognormal d50=150e-6 sigma=1.6 min=30e-6 max=600e-6\n"
                              "feed z=0.5 rate=2e-5\nrun 0.05")
    for name, sim in sims.items():
        png = sim._repr_png_()
        w, h = png_size(png)
        assert w >= 300 and h >= 300, (name, w, h)
        # the command and the method draw the same picture, and picture(path) keeps it
        path = tmp_path / (name + ".png")
        assert sim.picture(str(path)) == png and path.read_bytes() == png, name
        html = sim._repr_html_()
        assert "<img src='data:image/png;base64," in html and "<b>mote %s" % name in html, name


def test_no_picture_is_none_not_an_error():
    # charging draws no picture of its state; a system not made yet has nothing to draw
    assert mote.Simulation("charging")._repr_png_() is None
    assert "<img" not in mote.Simulation("charging")._repr_html_()
    empty = mote.NBody()
    assert empty._repr_png_() is None
    with pytest.raises(mote.MoteError, match="picture: there are no bodies yet"):
        empty.picture()


def test_picture_does_not_change_the_run():
    a, b = mote.HardSpheres(N=108, eta=0.4), mote.HardSpheres(N=108, eta=0.4)
    for sim in (a, b):
        sim.step(2)
    a._repr_html_()
    a.picture()
    for sim in (a, b):
        sim.step(2)
    assert a.state_bytes() == b.state_bytes()


def test_progress_line_outside_a_notebook(capsys):
    sim = mote.HardSpheres(N=108, eta=0.3)
    sim.step(20, progress=True)
    err = capsys.readouterr().err
    assert err.endswith("step 100%\n"), repr(err)
    sim.step(1)                                 # the default outside a notebook: nothing
    sim.step(1, progress=False)
    assert capsys.readouterr().err == ""


def test_progress_line_of_a_failed_command(capsys):
    def fails(bar):
        bar("step", 0.5)
        raise mote.MoteError("failed half way")
    with pytest.raises(mote.MoteError):
        mote._with_progress(fails, True)
    assert capsys.readouterr().err.endswith("step  50% (stopped)\n")
    # a function given is called as it is (no bar)
    calls = []
    mote.HardSpheres(N=108, eta=0.3).step(2, progress=lambda label, f: calls.append(label))
    assert calls and set(calls) == {"step"}
    assert capsys.readouterr().err == ""


def test_h5md_from_python(tmp_path):
    h5py = pytest.importorskip("h5py")
    sim = mote.NBody()
    sim.add(m=1)
    sim.add(m=1e-3, a=1, e=0.1)
    path = str(tmp_path / "orbit.h5")
    sim.command("trajectory dt=0.5 file=%s velocities=on" % path)
    sim.integrate(5)
    with h5py.File(path, "r") as f:
        x = f["particles/all/position/value"][:]
        t = f["particles/all/position/time"][:]
        assert x.shape == (11, 2, 3) and f["particles/all/velocity/value"].shape == (11, 2, 3)
        np.testing.assert_allclose(t, 0.5 * np.arange(11), rtol=0, atol=1e-12)
        np.testing.assert_array_equal(x[-1], sim.positions)


def test_h5md_stopped_by_ctrl_c(tmp_path, ctrl_c):
    """Ctrl-C stops the command at a safe point: the trajectory holds every frame so far, whole,
    and goes on growing when the simulation runs on."""
    h5py = pytest.importorskip("h5py")
    first_report, sent = ctrl_c()
    sim = mote.HardSpheres(N=500, eta=0.3)
    path = str(tmp_path / "t.h5")
    sim.command("trajectory every=1 file=%s format=h5md" % path)
    with pytest.raises(KeyboardInterrupt):
        sim.step(1000000, progress=first_report)  # minutes if not stopped
    with h5py.File(path, "r") as f:
        n = f["particles/all/position/value"].shape[0]
        assert sent and n >= 2 and not np.isnan(f["particles/all/position/value"][:]).any()
    sim.step(2)
    with h5py.File(path, "r") as f:
        x = f["particles/all/position/value"]
        assert x.shape[0] == n + 2 and not np.isnan(x[:]).any()
        np.testing.assert_array_equal(x[-1], sim.positions)
