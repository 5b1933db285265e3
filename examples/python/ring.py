"""The N-body model's exact tests from Python: the 30-body gravity ring against its exact motion,
and the outer Solar System's energy error, each over time, with mote.NBody (its generators and
`check` through sim.cmd, the commands as methods).

    python3 ring.py [--quick] [--out DIR]      (writes DIR/errors.png)
"""
import argparse
import os
import re

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

import mote

HERE = os.path.dirname(os.path.abspath(__file__))


def ring_errors(chunks, steps):
    """The ring (Galactica's scheme, dT = 1e-6): its largest relative position error against the
    exact solution after every `steps` steps."""
    sim = mote.NBody()
    sim.cmd.generate_ring(nb=30)
    sim.set_integrator("galactica", dt=1e-6)
    T, err = [], []
    for _ in range(chunks):
        sim.step(steps)
        printed = sim.cmd.check("ring")
        m = re.search(r"check ring: T = (\S+) .*: error (\S+),", printed)
        T.append(float(m.group(1)))
        err.append(float(m.group(2)))
    return T, err


def solar_errors(data, chunks, years):
    """The outer Solar System (Taylor, order 17): the relative energy error every `years`."""
    sim = mote.NBody()
    sim.cmd.generate_solar_system(data=data)
    sim.set_integrator("taylor", order=17, tol=3e-17)
    T, dE = [], []
    for k in range(1, chunks + 1):
        sim.cmd.integrate(to=k * years, unit="year")
        st = sim.status()
        T.append(k * years)
        dE.append(abs(st["dE"]))
    return T, dE


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a short run (for the tests)")
    ap.add_argument("--out", default="out/ring")
    ap.add_argument("--data", default=os.path.join(HERE, "..", "..", "data",
                                                   "outer_solar_system.dat"))
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    T, err = ring_errors(5 if a.quick else 20, 500)
    Ts, dE = solar_errors(a.data, 4 if a.quick else 20, 100 if a.quick else 500)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    ax1.semilogy(T, err, "o-")
    ax1.set_xlabel("T (ring units)")
    ax1.set_ylabel("largest relative position error")
    ax1.set_title("gravity ring, 30 bodies")
    ax2.semilogy(Ts, [max(e, 1e-18) for e in dE], "o-", color="C1")
    ax2.set_xlabel("t (years)")
    ax2.set_ylabel("|relative energy error|")
    ax2.set_title("outer Solar System")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "errors.png"), dpi=120)
    print("ring: error %.3e at T = %.6g; outer Solar System: |dE| %.3e at %g years"
          % (err[-1], T[-1], dE[-1], Ts[-1]))
    return T, err, Ts, dE


if __name__ == "__main__":
    main()
