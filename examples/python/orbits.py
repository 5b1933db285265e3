"""A star and two planets from orbital elements, integrated and drawn: the N-body model as a
REBOUND user's first script reads (mote.NBody: add, integrate, particles, orbit).

    python3 orbits.py [--quick] [--out DIR]      (writes DIR/orbits.png and DIR/orbits.traj)
"""
import argparse
import os

import mote


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a short run (for the tests)")
    ap.add_argument("--out", default="out/orbits")
    args = ap.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)

    sim = mote.NBody()                       # G = 1, the adaptive Taylor integrator
    sim.add(m=1, name="Star")
    sim.add(m=1e-3, a=1, e=0.1, name="b")    # about the star
    sim.add(m=1e-3, a=2.3, e=0.05, inc=0.05, M=2, name="c")  # about the star and b
    sim.move_to_com()                        # the centre of mass at rest at the origin
    for p in sim.particles[1:]:
        o = p.orbit()
        print("body %d: a = %.6f, e = %.6f, period %.4f" % (p.index, o["a"], o["e"], o["P"]))

    traj = os.path.join(args.out, "orbits.traj")
    sim.command("trajectory dt=0.05 file=%s" % traj)
    T = 20 if args.quick else 200            # (b's period is 2 pi)
    sim.integrate(T)
    print("t = %g: E = %.15g, dE = %.2e" % (sim.t, sim.energy(), sim.status()["dE"]))
    print(sim.particles[1])
    png = os.path.join(args.out, "orbits.png")
    sim.command("plot %s %s" % (traj, png))
    a = [p.orbit()["a"] for p in sim.particles[1:]]
    return sim.t, sim.status()["dE"], a


if __name__ == "__main__":
    main()
