"""The models as objects (issue 54): each method runs the command it names, so an object and
a script with the same lines give the same bits, and every check is the command's own (an
error is a MoteError with mote's message). `Simulation.command` stays for everything else.
The N-body model as REBOUND users write it:

    sim = mote.NBody()
    sim.add(m=1)
    sim.add(m=1e-3, a=1, e=0.05)
    sim.add(m=1e-3, a=2.5, e=0.1, inc=0.02, M=1.2)
    sim.integrate(100)
    sim.t, sim.energy(), sim.particles[1].x, sim.particles[2].orbit()["a"]
"""
import math

import numpy as _np

from . import MoteError, MoteIndexError, MoteTypeError, Simulation


def _num(v):
    """A value as the script reads it back exactly: integers as digits, reals as Python's
    shortest round-trip repr, True/False as on/off, text as it is."""
    import numbers
    if isinstance(v, str):
        return v
    if isinstance(v, bool):
        return "on" if v else "off"
    if isinstance(v, numbers.Integral):
        return str(int(v))
    return repr(float(v))


def _options(opts):
    return " ".join("%s=%s" % (k, _num(v)) for k, v in opts.items() if v is not None)


class Particle:
    """Body i of an NBody (0-based, as in REBOUND): its values read from the simulation when
    asked, and set through it (checked by the model)."""
    __slots__ = ("_sim", "_i")

    def __init__(self, sim, i):
        self._sim, self._i = sim, i

    def _get(self, name, k=None):
        a = self._sim.arrays()[name]
        return float(a[self._i] if k is None else a[self._i, k])

    def _set(self, name, k, value):
        a = self._sim.arrays()[name]
        a[self._i, k] = value
        self._sim.set(name, a)

    index = property(lambda self: self._i)
    m = property(lambda self: self._get("masses"))
    x = property(lambda self: self._get("positions", 0),
                 lambda self, v: self._set("positions", 0, v))
    y = property(lambda self: self._get("positions", 1),
                 lambda self, v: self._set("positions", 1, v))
    z = property(lambda self: self._get("positions", 2),
                 lambda self, v: self._set("positions", 2, v))
    vx = property(lambda self: self._get("velocities", 0),
                  lambda self, v: self._set("velocities", 0, v))
    vy = property(lambda self: self._get("velocities", 1),
                  lambda self, v: self._set("velocities", 1, v))
    vz = property(lambda self: self._get("velocities", 2),
                  lambda self, v: self._set("velocities", 2, v))
    xyz = property(lambda self: self._sim.arrays()["positions"][self._i].copy())
    vxyz = property(lambda self: self._sim.arrays()["velocities"][self._i].copy())

    def orbit(self, primary=None):
        """Its osculating orbital elements about `primary` (a Particle or an index; default:
        the centre of mass of the bodies before it, as `add` places it): a dict of a, e, inc,
        Omega, omega, f (radians), M (e < 1), P (the period, e < 1) and d (the distance)."""
        arr = self._sim.arrays()
        m, x, v = arr["masses"], arr["positions"], arr["velocities"]
        if primary is None:
            ks = list(range(self._i))
        else:
            ks = [primary._i if isinstance(primary, Particle) else int(primary)]
        M = float(sum(m[k] for k in ks))
        if not ks or M <= 0:
            raise MoteError("orbit: body %d has no primary with mass (give primary=)" % self._i)
        xp = sum(m[k] * x[k] for k in ks) / M
        vp = sum(m[k] * v[k] for k in ks) / M
        mu = M + float(m[self._i])  # (G = 1 inside)
        r, u = x[self._i] - xp, v[self._i] - vp
        d = float(_np.linalg.norm(r))
        h = _np.cross(r, u)
        hn = float(_np.linalg.norm(h))
        a = 1 / (2 / d - float(u @ u) / mu)
        ev = _np.cross(u, h) / mu - r / d
        e = float(_np.linalg.norm(ev))
        inc = math.acos(max(-1.0, min(1.0, h[2] / hn)))
        n = _np.array([-h[1], h[0], 0.0])
        hh = h / hn
        if _np.linalg.norm(n) == 0:  # in the plane z = 0: Omega 0, omega from the x axis
            Om, om = 0.0, math.atan2(ev[1], ev[0])
        else:
            Om = math.atan2(h[0], -h[1])
            om = math.atan2(float(_np.cross(n, ev) @ hh), float(n @ ev))
        f = math.atan2(float(_np.cross(ev, r) @ hh), float(ev @ r))
        out = {"a": a, "e": e, "inc": inc, "Omega": Om, "omega": om, "f": f, "d": d}
        if e < 1:
            E = 2 * math.atan(math.sqrt((1 - e) / (1 + e)) * math.tan(f / 2))
            out["M"] = E - e * math.sin(E)
            out["P"] = 2 * math.pi * math.sqrt(a ** 3 / mu)
        return out

    def __repr__(self):
        x, v = self.xyz, self.vxyz
        return "<mote.Particle %d m=%g x=(%g, %g, %g) v=(%g, %g, %g)>" % (
            self._i, self.m, x[0], x[1], x[2], v[0], v[1], v[2])


class Particles:
    """The bodies of an NBody as a sequence of Particle (negative indices count from the end)."""

    def __init__(self, sim):
        self._sim = sim

    def __len__(self):
        return int(self._sim.status()["N"])

    def __getitem__(self, i):
        n = len(self)
        if isinstance(i, slice):
            return [Particle(self._sim, k) for k in range(*i.indices(n))]
        k = i + n if i < 0 else i
        if not 0 <= k < n:
            raise MoteIndexError("body %d: there are %d" % (i, n))
        return Particle(self._sim, k)

    def __iter__(self):
        return (Particle(self._sim, k) for k in range(len(self)))


class NBody(Simulation):
    """The N-body model (`model nbody`, or `nbody coulomb` with coulomb=True) as objects:
    add (`body`), move_to_com (`frame barycentric`), integrate (`integrate to=`), step (`integrate
    steps=`), set_integrator (`integrator`), particles, t, N, energy(). units= is the `units` command's text ("solar
    input=dimensionless"); integrator= and its options choose the integrator (default: the
    adaptive Taylor integrator, mote's default)."""

    def __init__(self, coulomb=False, units=None, integrator=None, name="<python>", **options):
        Simulation.__init__(self, "nbody coulomb" if coulomb else "nbody", name)
        if units is not None:
            self.command("units " + units)
        if integrator is not None:
            self.set_integrator(integrator, **options)
        elif options:
            raise MoteTypeError("NBody: %s without integrator=" % ", ".join(sorted(options)))

    def add(self, m=None, r=None, primary=None, name=None, **elements):
        """`body`: m (mass), and x, y, z, vx, vy, vz, or orbital elements a, e, inc, Omega,
        omega, f or M about `primary` (a Particle, an index or a name; default: the centre of
        mass of the bodies so far); r (radius), charge, density, name. Returns the Particle."""
        mass = elements.pop("mass", m)
        radius = elements.pop("radius", r)
        if mass is None:
            raise MoteError("add: give the mass m=")
        opts = {"mass": mass, "radius": radius}
        opts.update(elements)
        if isinstance(primary, Particle):
            primary = primary.index
        if primary is not None:  # (body numbers count from 1; indices from 0)
            opts["primary"] = str(primary + 1) if isinstance(primary, int) else primary
        if name is not None:
            opts["name"] = name
        self.command("body " + _options(opts))
        return self.particles[-1]

    def move_to_com(self):
        """`frame barycentric`: the centre of mass to the origin, at rest (REBOUND's move_to_com)."""
        self.command("frame barycentric")

    def set_integrator(self, name, **options):
        """`integrator NAME OPTIONS` (galactica, taylor, wh)."""
        self.command(("integrator %s %s" % (name, _options(options))).rstrip())

    def integrate(self, t, progress=None):
        """`integrate to=t`: to the time t exactly."""
        return self.command("integrate to=" + _num(t), progress=progress)

    def step(self, n=1, progress=None):
        """`integrate steps=n`."""
        return self.command("integrate steps=%d" % n, progress=progress)

    particles = property(lambda self: Particles(self))
    t = property(lambda self: float(self.status()["T"]))
    N = property(lambda self: int(self.status()["N"]))

    def energy(self):
        """The total energy (the status line's E)."""
        return float(self.status()["E"])


class HardSpheres(Simulation):
    """The hard-sphere model (`model hard-spheres`) as an object: HardSpheres(N=4000, eta=0.45)
    is `bulk N eta` (a periodic FCC cube, N = 4 n^3), HardSpheres(NN=4, eta=0.3) is `new NN
    eta` (the slit between two walls, N = (4NN-1)(2NN-1)^2+1), seed= the `seed` before it;
    step (`step k`), pressure (`pressure K FILE`, its results as numbers), t, N, eta."""

    def __init__(self, N=None, eta=None, NN=None, seed=None, name="<python>"):
        Simulation.__init__(self, "hard-spheres", name)
        if seed is not None:  # (before the system: its velocities are drawn)
            self.command("seed %d" % seed)
        if (N is None) == (NN is None) and (N is not None or eta is not None):
            raise MoteError("HardSpheres: give N= (a periodic box) or NN= (a slit), with eta=")
        if NN is not None:
            self.command("new %d %s" % (NN, _num(eta)))
        elif N is not None:
            self.command("bulk %d %s" % (N, _num(eta)))

    def step(self, k=1, progress=None):
        """`step k`: k collisions per particle."""
        return self.command("step %d" % k, progress=progress)

    def pressure(self, k=10, file=None, progress=None):
        """`pressure k FILE` (FILE: a temporary file unless given): the measured values of the
        file's header as {name: (value, standard error)} (omega, P_virial, Z, rho)."""
        import os
        import tempfile
        from . import _quote, read_data
        with tempfile.TemporaryDirectory() as d:
            path = file or os.path.join(d, "pressure.dat")
            self.command("pressure %d %s" % (k, _quote(path)), progress=progress)
            h = read_data(path).header
        return {key: v for key, v in h.items() if isinstance(v, tuple)}

    t = property(lambda self: float(self.status()["t"]))
    N = property(lambda self: int(self.status()["N"]))
    eta = property(lambda self: float(self.status()["eta"]))


class _TimedModel(Simulation):
    """A model set up by its own command lines (seed= the `seed` before them) and advanced by
    `run T` (seconds): the mixing box and the separator share this much."""
    MODEL = None

    def __init__(self, setup=None, seed=None, name="<python>"):
        Simulation.__init__(self, self.MODEL, name)
        if seed is not None:  # (before the set-up, which may draw: place, insert)
            self.command("seed %d" % seed)
        if setup:
            self.command(setup)

    def run(self, t, progress=None):
        """`run t`: t seconds more."""
        return self.command("run " + _num(t), progress=progress)

    t = property(lambda self: float(self.status()["t"]))
    N = property(lambda self: int(self.status()["N"]))


class Separator(_TimedModel):
    """The gravitational separator (`model separator`) as an object: set up by its commands
    (Separator("channel 0.05 1\\ngas 1.5\\n..."), or sep.command(...) later), run (`run T`),
    tromp (`tromp FILE`: the grade-efficiency curve as a pandas DataFrame when pandas is there,
    its header's values (d50_m, kappa, ...) in .attrs; else the DataFile), t, N."""

    MODEL = "separator"

    def tromp(self, file=None):
        """`tromp FILE` (a temporary file unless given), read back."""
        import os
        import tempfile
        from . import _quote, read_data
        with tempfile.TemporaryDirectory() as d:
            path = file or os.path.join(d, "tromp.dat")
            self.command("tromp %s" % _quote(path))
            table = read_data(path)
        try:
            import pandas
        except ImportError:
            return table
        df = pandas.DataFrame(table.data, columns=table.columns)
        df.attrs.update(table.header)
        return df


class MixingBox(_TimedModel):
    """The mixing box (`model mixing-box`) as an object: set up by its commands (MixingBox("box
    0 0.4 0 0.2\\n...\\nplace")), run (`run t`), t, N, and the chambers' counts (the status's
    nL0 nL1 nR0 nR1: colour 0 and 1 left and right of the partition)."""

    MODEL = "mixing-box"

    def chambers(self):
        """{"left": (colour 0, colour 1), "right": (colour 0, colour 1)}: the disks in each."""
        st = self.status()
        return {"left": (int(st["nL0"]), int(st["nL1"])), "right": (int(st["nR0"]), int(st["nR1"]))}


class Charging(Simulation):
    """Spacecraft charging (`model charging`; faithful=True: `model charging faithful`) as an
    object: set up by its commands (Charging("plasma preset thesis-hot\\nbody sphere
    radius=1")), run (`run particles=N ...`: the currents to the uncharged body), float
    (`float ...`: the floating potential). The charging model has no state file, so it cannot
    be pickled or copied."""

    def __init__(self, setup=None, faithful=False, name="<python>"):
        Simulation.__init__(self, "charging faithful" if faithful else "charging", name)
        if setup:
            self.command(setup)

    def run(self, progress=None, **options):
        """`run OPTIONS` (particles=N, ...): what it printed."""
        return self.command(("run " + _options(options)).rstrip(), progress=progress)

    def float(self, progress=None, **options):
        """`float OPTIONS` (particles=, tolerance=, U0=, replicas=, roots=): {"U_f": volts,
        "sigma_U": its standard error, "U_oml": the OML estimate for the equivalent sphere
        without emission, "printed": what it printed}, the numbers as the command prints them
        (6 significant digits, well inside sigma_U). With dielectric parts, their steady state
        with the frame: U_oml is None, and "V" maps each part's name to its potential V_p and
        "sigma_dV" to the error of V_p - U (None where the command prints none)."""
        import re
        printed = self.command(("float " + _options(options)).rstrip(), progress=progress)
        m = re.search(r"^float: U_f = (\S+) V \+- (\S+) \(OML estimate, no emission, for the "
                      r"equivalent sphere (\S+) V", printed, re.M)
        if m:
            return {"U_f": float(m.group(1)), "sigma_U": float(m.group(2)),
                    "U_oml": float(m.group(3)), "printed": printed}
        m = re.search(r"^float: the steady state of the conductor and \d+ dielectric parts? .*: "
                      r"U = (\S+) V \+- ([^;]+);", printed, re.M)
        if not m:
            raise MoteError("float: no 'U_f = ...' or steady-state line in its output:\n" + printed)
        V, sdV = {}, {}
        for p in re.finditer(r"^float: dielectric (\S+): V_p = (\S+) V, V_p - U = \S+ V"
                             r"(?: \+- ([^;]+))?;", printed, re.M):
            V[p.group(1)] = float(p.group(2))
            sdV[p.group(1)] = float(p.group(3)) if p.group(3) else None
        return {"U_f": float(m.group(1)), "sigma_U": float(m.group(2)), "U_oml": None, "V": V,
                "sigma_dV": sdV, "printed": printed}
