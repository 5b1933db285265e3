"""Every command of a model as a Python method, made from the tables `mote help` prints.

    sim = mote.Simulation("hard-spheres")
    sim.cmd.new(2, 0.3)                              # `new 2 0.3`
    sim.cmd.trajectory(every=1, file="t.h5")         # `trajectory every=1 file=t.h5`
    help(sim.cmd.trajectory)                         # the command's help, its signature
    sim.cmd.snapshot(file="s.xyz", format="h5md")    # MoteError: mote's own check

Each method's signature comes from the command's argument spec (positional arguments, then
key=value options; `int`, `float`, `str`, the words of e{...} as typing.Literal, "X,Y,Z"
vectors as tuples) and its docstring is the command's help. Values are written as the command
line takes them (integers as digits, reals at full precision, True/False as on/off, tuples as
"x,y,z", names quoted when they need it); the command is then checked and run by mote exactly
as a script line, so its errors are mote's (MoteError with the line and column).
"""
import inspect
import keyword
import re
import typing

from ._mote import commands as _commands

_REAL = float
_VECTOR = typing.Tuple[float, float, float]


def _words(spec):
    m = re.search(r"\{([^}]*)\}", spec)
    return m.group(1).split("|") if m else []


def _annotation(spec):
    """The Python type of one argument spec ("i>=1", "r>0{auto}", "e{on|off}", "f>xyz", ...)."""
    words = _words(spec)
    letter = spec[:1]
    base = {"i": int, "u": int, "r": _REAL, "f": str, "s": str}.get(letter)
    if spec.startswith("v3"):
        base = _VECTOR
    elif spec.startswith("v2"):
        base = typing.Tuple[float, float]
    if letter == "e":
        return typing.Literal[tuple(words)] if words else str
    if words:
        return typing.Union[base, typing.Literal[tuple(words)]]
    return base or str


def _split(args):
    """The specs of a command: [(name or None, spec, required, bare)] (see command.h)."""
    out, positional = [], 0
    for tok in (args or "").split():
        opt = re.fullmatch(r"(@?)([A-Za-z_]\w*)=(.*)", tok)
        if opt:
            bare, key, spec = opt.group(1) == "@", opt.group(2), opt.group(3)
            required = spec.endswith("!")
            out.append((key, spec.rstrip("!"), required, bare))
        elif tok == "*":
            out.append(("*", "*", False, False))
        else:
            # plain letters may be run together: "ir" is "i r"
            parts = [tok] if not re.fullmatch(r"[iurfs]{2,}", tok) else list(tok)
            for p in parts:
                positional += 1
                out.append((None, p, True, False))
    return out


def _text(value, spec=""):
    """One value as the command line takes it."""
    if isinstance(value, bool):
        return "on" if value else "off"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, (tuple, list)):
        return ",".join(_text(v) for v in value)
    if hasattr(value, "__fspath__"):
        value = value.__fspath__()
    s = str(value)
    if s == "" or any(c.isspace() or c in '"#' for c in s):
        return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'
    return s


def _positional_names(synopsis, n):
    """The names of the n positional arguments, from the synopsis ("new NN eta" -> nn, eta)
    where it spells them, else arg1, arg2, ..."""
    words = [w for w in (synopsis or "").split()[1:]
             if "=" not in w and not w.startswith("[") and "|" not in w and "..." not in w]
    names = [re.sub(r"\W", "_", w).lower() for w in words][:n]
    if (len(names) == n and len(set(names)) == n
            and all(x.isidentifier() and not keyword.iskeyword(x) for x in names)):
        return names
    return ["arg%d" % (k + 1) for k in range(n)]


def _pyname(name):
    """A command's name as a Python name: "generate ring" -> generate_ring, import -> import_."""
    name = name.replace(" ", "_")
    return name + "_" if keyword.iskeyword(name) else name


# the script language's own lines, which are not commands of a simulation: the model (given
# when it is made) and the blocks (a loop or an ensemble is a script: sim.command("...") runs
# one whole)
_NOT_METHODS = ("model", "for", "end", "ensemble")


class Command:
    """One command of a model, bound to a simulation: call it with the command's arguments."""

    def __init__(self, sim, name, aliases, args, synopsis, summary, help_text):
        self._sim, self.name, self.synopsis = sim, name, synopsis
        self._specs = _split(args)
        names = _positional_names(synopsis, sum(1 for k, s, r, b in self._specs
                                                if k is None and not s.startswith("f+")))
        params = []
        for key, spec, required, bare in self._specs:
            if key == "*":
                params.append(inspect.Parameter("args", inspect.Parameter.VAR_POSITIONAL,
                                                annotation=str))
                continue
            if spec.startswith("f+"):
                params.append(inspect.Parameter("files", inspect.Parameter.VAR_POSITIONAL,
                                                annotation=str))
                continue
            if key is None:
                params.append(inspect.Parameter(names[len(params)],
                                                inspect.Parameter.POSITIONAL_ONLY,
                                                annotation=_annotation(spec)))
        # the positional specs are required in the table, but a command may take fewer
        # (its check says what it needs): they default to "not given"
        params = [p.replace(default=None) if p.kind == p.POSITIONAL_ONLY else p for p in params]
        for key, spec, required, bare in self._specs:
            if key not in (None, "*"):
                params.append(inspect.Parameter(
                    _pyname(key), inspect.Parameter.KEYWORD_ONLY,
                    default=inspect.Parameter.empty if required else None,
                    annotation=_annotation(spec)))
        params.append(inspect.Parameter("progress", inspect.Parameter.KEYWORD_ONLY, default=None))
        self.__signature__ = inspect.Signature(params, return_annotation=str)
        self.__doc__ = "%s\n\n%s\n\n%s" % (synopsis or name, summary or "", help_text or "")
        self.__name__ = _pyname(name)
        self.aliases = (aliases or "").split()

    def line(self, *args, **options):
        """The command line a call would run."""
        options.pop("progress", None)
        bound = self.__signature__.bind(*args, **options)
        words = [self.name]
        for name, value in bound.arguments.items():
            p = self.__signature__.parameters[name]
            if p.kind == p.VAR_POSITIONAL:
                words += [_text(v) for v in value]
            elif p.kind == p.POSITIONAL_ONLY:
                if value is not None:
                    words.append(_text(value))
            elif value is not None:
                key = name[:-1] if name.endswith("_") and keyword.iskeyword(name[:-1]) else name
                words.append("%s=%s" % (key, _text(value)))
        return " ".join(words)

    def __call__(self, *args, progress=None, **options):
        return self._sim.command(self.line(*args, **options), progress=progress)

    def __repr__(self):
        return "<mote command %s>" % (self.synopsis or self.name)


class Commands:
    """sim.cmd: the model's commands as methods (tab completion lists them; help() gives each
    command's documentation)."""

    def __init__(self, sim):
        self._sim = sim
        self._table = {}
        for row in _commands(sim._s.model):
            name = row[0]
            if name in _NOT_METHODS:
                continue
            self._table[_pyname(name)] = row
            for alias in (row[1] or "").split():
                self._table.setdefault(_pyname(alias), row)

    def __getattr__(self, name):
        row = self.__dict__.get("_table", {}).get(name)
        if row is None:
            raise AttributeError("the %s model has no command '%s' (dir(sim.cmd) lists them)"
                                 % (self._sim.model, name))
        return Command(self._sim, *row)

    def __dir__(self):
        return sorted(self._table)

    def __repr__(self):
        return "<the %d commands of mote %s>" % (len(self._table), self._sim.model)
