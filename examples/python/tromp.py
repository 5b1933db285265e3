"""A Tromp curve (grade efficiency) of the gravitational separator at three gas speeds.

Each speed is an ensemble of replicas; the cut size d50 and the sharpness kappa come back with
their standard errors (mote.read_data of the summary table), and the curves of the first
replica of each speed are plotted with matplotlib.

    python3 tromp.py [--quick] [--out DIR]      (writes DIR/tromp.png and DIR/tromp.dat)
"""
import argparse
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

import mote

SCRIPT = """
model separator
output_dir ${out}
for u in 0.8 1 1.2
    ensemble ${R} summary=tromp.dat
        channel 0.05 1
        gas ${u}
        coupling off
        collisions off
        species quartz 2500
        size quartz loguniform min=75e-6 max=300e-6 basis=number
        feed z=0.5
        classes 25 min=75e-6 max=316.2277660e-6
        timestep 1e-3
        insert quartz ${N}
        run 30
        tromp t_${u}_${replica}.dat
    end
end
"""


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a short run (for the tests)")
    ap.add_argument("--out", default="out/tromp")
    a = ap.parse_args(argv)
    out = os.path.abspath(a.out)
    R, N = (2, 1000) if a.quick else (4, 8000)
    mote.run(SCRIPT, out=out, R=R, N=N)
    table = mote.read_data(os.path.join(out, "tromp.dat"))
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for u in ("0.8", "1", "1.2"):
        t = mote.read_data(os.path.join(out, "t_%s_1.dat" % u))
        ax.semilogx(t.column("d_mean_m") * 1e6, t.column("T_mass"), "o-", label="u = %s m/s" % u)
    ax.set_xlabel("particle diameter ($\\mu$m)")
    ax.set_ylabel("grade efficiency T (mass to the coarse outlet)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "tromp.png"), dpi=120)
    u = table.column("u")
    d50, dd50 = table.column("tromp.d50"), table.column("tromp.d50_err")
    for k in range(len(u)):
        print("u = %.2g m/s: d50 = %.2f ± %.2f um, kappa = %.3f"
              % (u[k], d50[k] * 1e6, dd50[k] * 1e6, table.column("tromp.kappa")[k]))
    return u, d50, dd50


if __name__ == "__main__":
    main()
