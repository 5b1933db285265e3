"""Persistence (issue 54, item 4): a Simulation pickled, copied or loaded from its state file
continues bit for bit as the one that never stopped, in every model with a state file; a model
without one says so."""
import copy
import pickle

import pytest

import mote

SEP = ("channel 0.05 1\ngas 1.5\ncollisions off\ntimestep 1e-3\nspecies quartz 2650\n"
       "size quartz lognormal d50=150e-6 sigma=1.6 min=30e-6 max=600e-6\nfeed z=0.5 rate=2e-5\n")
# model, the set-up and first stretch, the second stretch
CASES = [
    ("hard-spheres", "new 2 0.3\nstep 300", "step 300"),
    ("hard-spheres", "bulk_disks 36 0.5\nstep 300", "step 300"),
    ("mixing-box", "box 0 0.4 0 0.2\npartition 0.2 0.01\nslit 0.1 0.04\nradius 0.004\n"
                   "disks 30 20\nv_init 1\nplace\nrun 0.05", "run 0.05"),
    ("nbody", "generate ring nb=8\nintegrate steps=20", "integrate steps=20"),
    ("nbody", "integrator wh dt=0.01\nbody mass=1\nbody mass=1e-3 x=1 vy=1\n"
              "body mass=1e-4 x=2 vy=0.7\nintegrate steps=25", "integrate steps=25"),
    ("nbody coulomb", "body mass=1 charge=1\nbody mass=1 charge=-1 x=1 vy=1\nintegrate steps=10",
     "integrate steps=10"),
    ("separator", SEP + "run 0.02", "run 0.02"),
]


def start(model, first):
    s = mote.Simulation(model)
    s.command(first)
    return s


@pytest.mark.parametrize("model,first,second", CASES)
def test_pickle_copy_load_continue_bit_for_bit(model, first, second, tmp_path):
    ref = start(model, first)
    ref.command(second)  # the run that never stopped
    s = start(model, first)
    data = pickle.dumps(s)
    saved = s.state_bytes()
    twins = [pickle.loads(data), copy.deepcopy(s), copy.copy(s)]
    (tmp_path / "s.state").write_bytes(saved)
    twins.append(mote.load(str(tmp_path / "s.state")))
    s.command(second)  # the pickled one goes on unchanged too
    want = ref.state_bytes()
    assert s.state_bytes() == want
    for t in twins:
        assert t.model == model.split()[0] and t is not s
        t.command(second)
        assert t.state_bytes() == want
    # each owns its model: running one leaves the other
    twins[1].command(second)
    assert twins[2].state_bytes() == want


def test_no_state_file():
    c = mote.Simulation("charging")
    with pytest.raises(mote.MoteError, match=r"the charging model has no state file"):
        pickle.dumps(c)


def test_load_errors(tmp_path):
    with pytest.raises(mote.MoteError, match=r"nothere.state: cannot open"):
        mote.load(str(tmp_path / "nothere.state"))
    (tmp_path / "x.state").write_text("hello\n")
    with pytest.raises(mote.MoteError, match=r"x.state:1: not a mote state file"):
        mote.load(str(tmp_path / "x.state"))
    (tmp_path / "y.state").write_text("mote-state 1\nmodel warp-drive\n")
    with pytest.raises(mote.MoteError, match=r"y.state:2: no model 'warp-drive'"):
        mote.load(str(tmp_path / "y.state"))
    # a file of one endless line (read 4 KiB at most, not whole) and a folder
    (tmp_path / "w.state").write_bytes(b"m" * 20_000_000)
    with pytest.raises(mote.MoteError, match=r"w.state:1: not a mote state file"):
        mote.load(str(tmp_path / "w.state"))
    with pytest.raises(mote.MoteError, match=r"cannot open"):
        mote.load(str(tmp_path))
    (tmp_path / "z.state").write_text("mote-state 1\nmodel nbody\ninteraction gravity\nn 2\n")
    with pytest.raises(mote.MoteError, match=r"z.state:5"):
        mote.load(str(tmp_path / "z.state"))


def test_interrupted_then_saved_and_continued(ctrl_c):
    """Ctrl-C mid-command leaves a state that saves and continues as the original does (the
    interrupted hard-sphere run had rebuilt its calendar mid-stretch: its save wrote the
    rebuild's coordinates, which load refused, until the engine kept track)."""
    first_report, sent = ctrl_c()
    sim = mote.Simulation()
    sim.command("new 4 0.3")
    with pytest.raises(KeyboardInterrupt):
        sim.command("step 1000000", progress=first_report)
    twin = copy.deepcopy(sim)
    sim.command("step 20")
    twin.command("step 20")
    assert sent and twin.state_bytes() == sim.state_bytes()
