# Every failure of mote is a MoteError with mote's message (the file and line where there is
# one); the ones that are also Python's own kinds (a body past the last, a missing column,
# options that do not fit) are MoteIndexError, MoteKeyError and MoteTypeError, both at once.
import pytest

import mote


def test_files_named(tmp_path):
    with pytest.raises(mote.MoteError, match="no-such.mote: cannot read the script: No such file"):
        mote.run_file(str(tmp_path / "no-such.mote"))
    binary = tmp_path / "b.mote"
    binary.write_bytes(b"\xff\xfe\x00model nbody\n")
    with pytest.raises(mote.MoteError, match=r"b\.mote: not a script \(not UTF-8 text"):
        mote.run_file(str(binary))
    sim = mote.HardSpheres(N=108, eta=0.3)
    with pytest.raises(mote.MoteError, match="x.png: cannot write the picture"):
        sim.picture(str(tmp_path / "no-dir" / "x.png"))
    with pytest.raises(mote.MoteError, match="no-such.dat: cannot open"):
        mote.read_data(str(tmp_path / "no-such.dat"))


def test_values_and_state_bytes():
    sim = mote.HardSpheres(N=108, eta=0.3)
    with pytest.raises(mote.MoteError, match=r"set positions: expected numbers"):
        sim.set("positions", [["a", "b", "c"]])
    with pytest.raises(mote.MoteError, match=r"<python>:\d+:\d+: error: <state bytes>:1: not a "
                                             r"state file \(found 'garbage'\)"):
        sim.load_bytes(b"garbage")


def test_both_kinds(tmp_path):
    with pytest.raises(mote.MoteIndexError, match="body 3: there are 0") as e:
        mote.NBody().particles[3]
    assert isinstance(e.value, IndexError)
    assert list(mote.NBody().particles) == []         # (iteration still ends on IndexError)
    with pytest.raises(TypeError, match="NBody: tol without integrator=") as e:
        mote.NBody(tol=1e-10)
    assert isinstance(e.value, mote.MoteError)
    sim = mote.HardSpheres(N=108, eta=0.3)
    path = str(tmp_path / "p.dat")
    sim.pressure(2, file=path)
    with pytest.raises(KeyError, match=r"p\.dat has no column nope \(its columns: ") as e:
        mote.read_data(path).column("nope")
    assert isinstance(e.value, mote.MoteError)
