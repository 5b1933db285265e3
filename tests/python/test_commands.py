# sim.cmd: every command as a method, made from the command tables (mote.commands).
import inspect
import typing

import pytest

import mote
from mote import _mote


def test_every_command_of_every_model_is_a_method():
    for model in mote.models():
        sim = mote.Simulation(model)
        rows = _mote.commands(model)
        names = {r[0].replace(" ", "_") for r in rows} - {"model", "for", "end", "ensemble"}
        assert names and names <= set(dir(sim.cmd)), (model, names - set(dir(sim.cmd)))
        for name, aliases, args, synopsis, summary, help_text in rows:
            if name in ("model", "for", "end", "ensemble"):
                continue
            c = getattr(sim.cmd, name.replace(" ", "_"))
            assert inspect.signature(c).return_annotation is str
            assert summary in c.__doc__ and (help_text or "") in c.__doc__
            for alias in (aliases or "").split():
                assert getattr(sim.cmd, alias).name == name


def test_signatures_from_the_specs():
    sim = mote.Simulation("hard-spheres")
    sig = inspect.signature(sim.cmd.trajectory)
    assert sig.parameters["file"].default is inspect.Parameter.empty  # file=f>xyz! is required
    assert sig.parameters["every"].annotation is int
    assert sig.parameters["dt"].annotation is float
    assert sig.parameters["format"].annotation == typing.Literal["xyz", "h5md"]
    new = inspect.signature(sim.cmd.new)
    assert list(new.parameters)[:2] == ["nn", "eta"]  # named as the synopsis names them
    assert inspect.signature(mote.NBody().cmd.integrate).parameters["for_"].annotation is float
    assert mote.NBody().cmd.generate_ring.line(nb=30) == "generate ring nb=30"


def test_calls_run_the_same_lines():
    a, b = mote.Simulation("hard-spheres"), mote.Simulation("hard-spheres")
    a.cmd.seed(7)
    a.cmd.new(3, 0.4)
    a.cmd.step(2)
    b.command("seed 7\nnew 3 0.4\nstep 2")
    assert a.state_bytes() == b.state_bytes()
    nb = mote.NBody()
    assert nb.cmd.body.line(mass=1.0, x=0.1, name="a star") == 'body mass=1.0 x=0.1 name="a star"'
    assert nb.cmd.merge.line(False) == "merge off"
    assert nb.cmd.body.line(mass=1, spin=(0, 0, 1.5)) == "body mass=1 spin=0,0,1.5"
    assert nb.cmd.integrate.line(for_=2.5) == "integrate for=2.5"


def test_errors():
    sim = mote.Simulation("hard-spheres")
    sim.cmd.new(2, 0.3)
    with pytest.raises(TypeError):
        sim.cmd.trajectory(every=1, file="t.xyz", colour="red")  # no such option
    with pytest.raises(mote.MoteError, match=r"trajectory: FILE must end in \.xyz"):
        sim.cmd.trajectory(every=1, file="t.dat")             # mote's own check
    with pytest.raises(AttributeError, match="has no command 'fly'"):
        sim.cmd.fly
