"""mote: the particle-simulation toolkit from Python.

    import mote
    printed = mote.run("model nbody\\ngenerate ring nb=30\\nintegrate to=0.01\\n")
    sim = mote.Simulation("nbody")
    sim.command("generate ring nb=30")
    sim.command("integrate to=0.01")
    sim.status()["dE"], sim.positions          # a dict; a NumPy array
    table = mote.read_data("out/p.dat")         # columns, header and rows of a data file
    twin = copy.deepcopy(sim)                   # or pickle; mote.load("ring.state")

The commands and scripts are mote's own (`mote help`, docs/commands.md): the package runs them
through libmote, so its results are bit for bit those of `mote run` with the same lines. Errors
are raised as MoteError with mote's message ("FILE:LINE:COL: error: ..."); nothing of a script
runs when it does not check. Runs release the GIL.
"""
import os as _os
import re as _re
import sys as _sys

import numpy as _np

# libgomp reads its spin count once, when it is loaded with the extension below: threads that spin
# 1000 rounds, not 300 000, before they sleep are never slower than one on a busy machine
# (mote_threads_quiet in core.h). The user's own setting wins.
if "GOMP_SPINCOUNT" not in _os.environ and "OMP_WAIT_POLICY" not in _os.environ:
    _os.environ["GOMP_SPINCOUNT"] = "1000"

from ._mote import MoteError, Session as _Session, models as _models, version as __version__
from . import _mote


# Failures that are also Python's own kinds, so that `except MoteError` catches every failure of
# mote and Python's protocols (iteration, indexing, keyword arguments) still see theirs.
class MoteIndexError(MoteError, IndexError):
    """No such item (a body number past the last): a MoteError and an IndexError."""


class MoteKeyError(MoteError, KeyError):
    """No such key (a column a data file lacks): a MoteError and a KeyError."""

    def __str__(self):  # (not KeyError's quoted repr)
        return str(self.args[0]) if self.args else ""


class MoteTypeError(MoteError, TypeError):
    """Arguments that do not fit (options without what they belong to): a MoteError and a
    TypeError."""


def _os_error(path, what, e):
    """An OSError as a MoteError naming the file."""
    return MoteError("%s: cannot %s: %s" % (path, what, e.strerror or e))

__all__ = ["run", "run_file", "check", "Simulation", "NBody", "Particle", "HardSpheres",
           "MixingBox", "Charging", "Separator", "load", "read_data", "DataFile", "MoteError",
           "MoteIndexError", "MoteKeyError", "MoteTypeError", "models", "__version__"]


def models():
    """The names of the models of this build."""
    return _models()


def _params(params):
    out = []
    for k, v in params.items():
        out.append("%s=%s" % (k, v))
    return out


def run(script, name="<python>", progress=None, echo=False, **params):
    """Check, then run a script given as text; keyword arguments are its parameters (as
    `mote run SCRIPT NAME=VALUE`). Returns what it printed (also printed when echo is true);
    warnings go to the warnings module. progress(label, fraction) is called during long
    commands (at most every quarter second); True: a bar (a line on stderr outside a
    notebook); False: none; by default a bar in a notebook only. Raises MoteError (nothing
    runs when the script does not check; its .printed holds what ran before an error while
    running)."""
    printed, warnings_text = _with_progress(
        lambda bar: _mote.run(script, name, _params(params), False, bar), progress)
    _warn(warnings_text)
    if echo:
        print(printed, end="")
    return printed


def run_file(path, progress=None, echo=False, **params):
    """run() on a script file; its relative file names start from the script's folder, as
    with `mote run`."""
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except OSError as e:
        raise _os_error(path, "read the script", e) from None
    except UnicodeDecodeError as e:
        raise MoteError("%s: not a script (not UTF-8 text: %s)" % (path, e.reason)) from None
    return run(text, name=path, progress=progress, echo=echo, **params)


def check(script, name="<python>", **params):
    """Check a script as `mote check` does, running nothing; raises MoteError."""
    _, warnings_text = _mote.run(script, name, _params(params), True, None)
    _warn(warnings_text)


def _warn(text):
    if text:
        import warnings
        for line in text.splitlines():
            if line:
                warnings.warn(line, stacklevel=3)


_NUMBER = _re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


def _value(text):
    if _NUMBER.match(text):
        if _re.match(r"^[-+]?\d+$", text):
            return int(text)
        return float(text)
    if text in ("nan", "-nan", "inf", "-inf"):
        return float(text.replace("-nan", "nan"))
    return text


def _status_dict(line):
    d = {}
    for tok in line.split():
        if "=" in tok:
            k, v = tok.split("=", 1)
            d[k] = _value(v)
    return d


# ---- progress: a bar in a notebook, a line on a terminal ----

def _in_notebook():
    """Inside a Jupyter kernel (IPython's ZMQ shell)? IPython is imported there already."""
    ipy = _sys.modules.get("IPython")
    shell = ipy.get_ipython() if ipy is not None and hasattr(ipy, "get_ipython") else None
    return type(shell).__name__ == "ZMQInteractiveShell"


class _Bar:
    """progress=True (and the default in a notebook): the command's name and the fraction done,
    drawn in place; `done()` when the command has returned."""

    def __init__(self):
        self._shown, self._label, self._fraction = False, "", 0.0
        self._notebook = _in_notebook()
        if self._notebook:
            from IPython.display import HTML, display
            self._HTML, self._display, self._handle = HTML, display, None

    def _html(self, failed=False):
        import html
        colour = "#c0392b" if failed else "#2e86c1"
        return ("<div><progress value='%.4f' max='1' style='width:24em;accent-color:%s'>"
                "</progress> <code>%s</code> %3.0f%%</div>"
                % (self._fraction, colour, html.escape(self._label), 100 * self._fraction))

    def __call__(self, label, fraction):
        self._label, self._fraction = label, fraction
        if self._notebook:
            if self._handle is None:
                self._handle = self._display(self._HTML(self._html()), display_id=True)
            else:
                self._handle.update(self._HTML(self._html()))
        else:
            _sys.stderr.write("\r%s %3.0f%%" % (label, 100 * fraction))
            _sys.stderr.flush()
        self._shown = True

    def done(self, failed=False):
        if not self._shown:
            return
        if not failed:
            self._fraction = 1.0
        if self._notebook:
            self._handle.update(self._HTML(self._html(failed)))
        else:
            _sys.stderr.write("\r%s %3.0f%%%s\n" % (self._label, 100 * self._fraction,
                                                     " (stopped)" if failed else ""))
            _sys.stderr.flush()


def _progress(progress):
    """What a command reports to: the caller's function; a bar for progress=True, and by
    default inside a notebook; nothing for progress=False (or None outside a notebook)."""
    if progress is True or (progress is None and _in_notebook()):
        return _Bar()
    return None if progress is None or progress is False else progress


def _with_progress(call, progress):
    bar = _progress(progress)
    try:
        out = call(bar)
    except BaseException:
        if isinstance(bar, _Bar):
            bar.done(failed=True)
        raise
    if isinstance(bar, _Bar):
        bar.done()
    return out


class Simulation:
    """One model driven command by command:

        sim = mote.Simulation("hard-spheres")
        sim.command("new 2 0.3")             # what it printed, as text
        sim.command("step 100")
        sim.status()                         # {'N': 64, 'eta': 0.3, 't': ..., ...}
        x = sim.positions                    # a copy, in the users' numbering
        v = sim.view("positions")            # read-only view where the model's layout allows

    Each command is checked as a script line is (against everything before it) and then run;
    an error raises MoteError and leaves the system as it was before that command.
    `model` is a model name, with a variant where it has one ("nbody coulomb").
    """

    def __init__(self, model="hard-spheres", name="<python>"):
        self._s = _Session(model, name)
        self._spec, self._name = model, name

    def picture(self, path=None):
        """The model's picture of its state now (the `picture FILE.png` command) as PNG bytes,
        also kept in `path` when one is given; MoteError for a model without one (charging)
        or with nothing to draw yet."""
        import tempfile
        with tempfile.TemporaryDirectory() as d:
            tmp = _os.path.join(d, "picture.png")
            self.command("picture %s" % _quote(tmp), progress=False)
            with open(tmp, "rb") as f:
                data = f.read()
        if path is not None:
            try:
                with open(path, "wb") as f:
                    f.write(data)
            except OSError as e:
                raise _os_error(path, "write the picture", e) from None
        return data

    def _repr_png_(self):
        """In a notebook: the picture (None when the model has none, or nothing to draw)."""
        try:
            return self.picture()
        except MoteError:
            return None

    def _repr_html_(self):
        """In a notebook: the picture (where the model draws one) above the model's status
        line as a table."""
        import base64
        import html
        rows = "".join("<tr><th style='text-align:left'>%s</th><td>%s</td></tr>"
                       % (html.escape(str(k)), html.escape(str(v)))
                       for k, v in self.status().items())
        png = self._repr_png_()
        img = ("<img src='data:image/png;base64,%s' style='max-width:48em'/><br/>"
               % base64.b64encode(png).decode("ascii")) if png else ""
        return ("%s<table><caption style='text-align:left'><b>mote %s</b></caption>%s</table>"
                % (img, html.escape(self.model), rows))

    # ---- persistence: the exact state file (`save`, `load`) ----

    def state_bytes(self):
        """The model's exact state file (what `save` writes) as bytes; MoteError for a model
        that has no state file (charging)."""
        import tempfile
        with tempfile.TemporaryDirectory() as d:
            path = _os.path.join(d, "state")
            try:
                self.command("save %s" % _quote(path))
            except MoteError as e:
                if "unknown command" in str(e):
                    raise MoteError("the %s model has no state file (no save command): it "
                                    "cannot be pickled or copied" % self.model) from None
                raise
            with open(path, "rb") as f:
                return f.read()

    def load_bytes(self, data):
        """Replace the state by a state file's bytes (as `load` does)."""
        import tempfile
        with tempfile.TemporaryDirectory() as d:
            path = _os.path.join(d, "state")
            with open(path, "wb") as f:
                f.write(data)
            try:
                self.command("load %s" % _quote(path))
            except MoteError as e:  # (the temporary file's name means nothing to the caller)
                raise MoteError(str(e).replace(path, "<state bytes>")) from None

    def __getstate__(self):
        return {"model": self._spec, "name": self._name, "state": self.state_bytes()}

    def __setstate__(self, st):
        Simulation.__init__(self, st["model"], st["name"])  # (not a subclass's set-up)
        self.load_bytes(st["state"])

    def __deepcopy__(self, memo=None):
        """A new simulation from this one's exact state file (continues bit for bit alike)."""
        c = type(self).__new__(type(self))  # (mote.NBody stays an NBody)
        c.__setstate__(self.__getstate__())
        return c

    def __copy__(self):
        """As deepcopy: a copy shares nothing, each owns its model."""
        return self.__deepcopy__()

    @property
    def model(self):
        return self._s.model

    @property
    def cmd(self):
        """Every command of the model as a method, made from the same tables as `mote help`
        (mote.commands): `sim.cmd.step(100)`, `sim.cmd.trajectory(every=1, file="t.h5")`;
        help(sim.cmd.NAME) shows the command's documentation and signature."""
        from .commands import Commands
        return Commands(self)

    def command(self, text, progress=None, echo=False):
        """Read, check and run one or more lines; returns what they printed. progress: a
        function(label, fraction) called during long commands, True for a bar (in a notebook,
        or a line on stderr), False for none; by default a bar in a notebook only."""
        printed = _with_progress(lambda bar: self._s.command(text, bar), progress)
        if echo:
            print(printed, end="")
        return printed

    def status(self):
        """The model's status line as a dict of numbers (and words)."""
        return _status_dict(self._s.status())

    def status_line(self):
        return self._s.status().rstrip("\n")

    def arrays(self):
        """The state as {name: NumPy array} copies."""
        return {name: a for name, a, unit, view in self._s.arrays(True)}

    def units(self):
        return {name: unit for name, a, unit, view in self._s.arrays(True)}

    def view(self, name):
        """The array `name` as a read-only view of the model's own memory where its layout
        allows (nbody), else a copy. No command runs while a view is alive (delete it first)."""
        for n, a, unit, view in self._s.arrays(False):
            if n == name:
                return a
        raise MoteError("the %s model has no array '%s' (it has: %s)"
                        % (self.model, name, ", ".join(self.arrays())))

    def set(self, name, values):
        """Replace a state array (shape and values checked by the model)."""
        try:
            a = _np.asarray(values, dtype=float)
        except (TypeError, ValueError) as e:
            raise MoteError("set %s: expected numbers (%s)" % (name, e)) from None
        self._s.set_array(name, a)

    def _get(self, name):
        a = self.arrays()
        if name not in a:
            raise AttributeError("the %s model has no %s" % (self.model, name))
        return a[name]

    positions = property(lambda self: self._get("positions"))
    velocities = property(lambda self: self._get("velocities"))
    radii = property(lambda self: self._get("radii"))
    masses = property(lambda self: self._get("masses"))
    charges = property(lambda self: self._get("charges"))
    species = property(lambda self: self._get("species"))

    def to_ase(self):
        """The configuration as an ase.Atoms (ASE, Debian's python3-ase) for every model whose
        arrays are particles with radii (positions, velocities, radii: the hard-sphere,
        mixing-box and separator models of this version): positions (2D ones with z = 0),
        velocities, the radii as the array "radius" and the species as tags; the model's box as
        the cell (as the Lattice of its XYZ files: the hard spheres' box with x across the slit,
        the mixing box's walls, the separator's channel W x D x H; 0 along an axis the positions
        lack), its lower corner as the cell's displacement (celldisp), its periodic axes as
        pbc."""
        import ase
        a = self.arrays()
        if not all(k in a for k in ("positions", "velocities", "radii")):
            raise MoteError("to_ase: the %s model's arrays are not particles with radii "
                            "(ASE needs positions, velocities and radii; this model has %s)"
                            % (self.model, ", ".join(sorted(a)) or "none"))

        def three(v):
            return _np.column_stack([v, _np.zeros(len(v))]) if v.shape[1] == 2 else v

        atoms = ase.Atoms(positions=three(a["positions"]))
        atoms.set_velocities(three(a["velocities"]))
        atoms.set_array("radius", a["radii"])
        if "species" in a:
            atoms.set_tags(a["species"])
        box = self._s.cell()
        if box is not None:
            edges, corner, periodic = box
            atoms.set_cell(list(edges))
            atoms.set_celldisp(list(corner))
            atoms.set_pbc(list(periodic))
        return atoms

    def close(self):
        self._s.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _quote(path):
    """A file name as a script word: in double quotes, with \\ and \" escaped."""
    return '"%s"' % path.replace("\\", "\\\\").replace('"', '\\"')


def load(path, name="<python>"):
    """A Simulation from a state file written by `save` (or `checkpoint`), of whichever model
    (and variant) the file names; continuing it is bit for bit as continuing the run that
    wrote it."""
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            head = [f.readline(4096).strip() for _ in range(8)]  # (bounded: any file)
    except OSError as e:
        raise MoteError("%s: cannot open: %s" % (path, e.strerror or e)) from None
    if len(head) < 2 or not head[0].startswith("mote-state") or not head[1].startswith("model "):
        raise MoteError("%s:1: not a mote state file (it starts 'mote-state V', 'model NAME')"
                        % path)
    model = head[1].split()[1]
    if model not in _models():
        raise MoteError("%s:2: no model '%s' in this build (models: %s)"
                        % (path, model, ", ".join(_models())))
    variants = (_mote.variants(model) or "").split("|")
    words = {w for line in head[2:] for w in line.split()[1:2]}
    chosen = [v for v in variants[1:] if v in words]
    sim = Simulation(model + (" " + chosen[0] if chosen else ""), name)
    sim.command("load %s" % _quote(_os.path.abspath(path)))
    return sim


class DataFile:
    """A mote data file: .format, .command, .header (key -> number, or (value, error) for
    results), .columns (names), .blocks (a 2D array per block of rows), .data (the rows after
    the last '# columns:' line, the last block, as `plot` draws them) and .column(name)."""

    def __init__(self, path):
        self.path = path
        self.format = ""
        self.command = ""
        self.header = {}
        self.columns = []
        self.blocks = []
        rows = []
        try:
            f = open(path, encoding="utf-8")
        except OSError as e: # mote's error, naming the file, as every reader of mote's files
            raise MoteError("%s: cannot open: %s" % (path, e.strerror or e)) from None
        with f:
            for n, line in enumerate(f, 1):
                line = line.rstrip("\r\n")
                if n == 1:
                    m = _re.match(r"^# mote (\S+) 1$", line)
                    if not m:
                        raise MoteError("%s:1: not a mote data file (its first line is not "
                                        "'# mote FORMAT 1')" % path)
                    self.format = m.group(1)
                    continue
                if line.startswith("# command: "):
                    self.command = line[len("# command: "):]
                elif line.startswith("# columns:"):
                    self.columns = line[len("# columns:"):].split()
                elif line.startswith("#"):
                    m = _re.match(r"^# (\S+) = (\S+)(?: ± (\S+))?$", line)
                    if m:
                        v = _value(m.group(2))
                        self.header[m.group(1)] = (v, _value(m.group(3))) if m.group(3) else v
                elif not line.strip():
                    if rows:
                        self.blocks.append(rows)
                        rows = []
                else:
                    try:
                        rows.append([float(t) for t in line.split()])
                    except ValueError:
                        raise MoteError("%s:%d: not a row of numbers: %s" % (path, n, line))
        if rows:
            self.blocks.append(rows)
        self.blocks = [_np.array(b, dtype=float) if len({len(r) for r in b}) == 1
                       else _np.array(b, dtype=object) for b in self.blocks]

    @property
    def data(self):
        return self.blocks[-1] if self.blocks else _np.empty((0, len(self.columns)))

    def column(self, name):
        """The column `name` of .data (a name may leave out its [unit])."""
        for k, c in enumerate(self.columns):
            if c == name or c.split("[")[0] == name:
                return self.data[:, k]
        raise MoteKeyError("%s has no column %s (its columns: %s)"
                       % (self.path, name, ", ".join(self.columns)))

    def __repr__(self):
        return "DataFile(%r, format=%r, %d columns, %d rows)" % (
            self.path, self.format, len(self.columns), len(self.data))


def read_data(path):
    """Read a mote data file (see DataFile)."""
    return DataFile(path)


from .objects import (Charging, HardSpheres, MixingBox, NBody, Particle,  # noqa: E402
                      Separator)
