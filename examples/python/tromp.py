"""A Tromp curve (grade efficiency) of the gravitational separator at three gas speeds.

Each speed runs R replicas (seeds 1 ... R, side by side in Python threads) of mote.Separator:
a batch of quartz fed at mid-height, 30 s of flow, then its Tromp curve as a pandas DataFrame
whose .attrs hold the cut size d50 and the sharpness kappa; their means and standard errors
over the replicas are printed, and the first replica's curve of each speed is plotted with
matplotlib. (The same replicas as an `ensemble R` ... `end` of the same lines.)

    python3 tromp.py [--quick] [--out DIR]      (writes DIR/tromp.png and DIR/tromp.dat)
"""
import argparse
import os
from concurrent.futures import ThreadPoolExecutor

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import mote

SETUP = """
channel 0.05 1
gas {u}
coupling off
collisions off
species quartz 2500
size quartz loguniform min=75e-6 max=300e-6 basis=number
feed z=0.5
classes 25 min=75e-6 max=316.2277660e-6
timestep 1e-3
insert quartz {N}
"""


def replica(u, N, seed):
    """The Tromp curve of one replica (a DataFrame; d50_m and kappa in .attrs)."""
    sep = mote.Separator(SETUP.format(u=u, N=N), seed=seed)
    sep.run(30)
    return sep.tromp()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a short run (for the tests)")
    ap.add_argument("--out", default="out/tromp")
    a = ap.parse_args(argv)
    out = os.path.abspath(a.out)
    os.makedirs(out, exist_ok=True)
    R, N = (2, 1000) if a.quick else (4, 8000)
    u = np.array([0.8, 1.0, 1.2])
    with ThreadPoolExecutor(max_workers=os.cpu_count()) as pool:
        curves = [list(pool.map(lambda s, v=v: replica(v, N, s), range(1, R + 1))) for v in u]
    d = np.array([[c.attrs["d50_m"] for c in cs] for cs in curves])
    k = np.array([[c.attrs["kappa"] for c in cs] for cs in curves])
    d50, dd50 = d.mean(axis=1), d.std(axis=1, ddof=1) / np.sqrt(R)
    np.savetxt(os.path.join(out, "tromp.dat"), np.column_stack([u, d50, dd50, k.mean(axis=1)]),
               header="u_m_s d50_m d50_err_m kappa  (%d replicas of %d particles)" % (R, N))
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for v, cs in zip(u, curves):
        ax.semilogx(cs[0]["d_mean_m"] * 1e6, cs[0]["T_mass"], "o-", label="u = %g m/s" % v)
    ax.set_xlabel("particle diameter ($\\mu$m)")
    ax.set_ylabel("grade efficiency T (mass to the coarse outlet)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "tromp.png"), dpi=120)
    for j in range(len(u)):
        print("u = %.2g m/s: d50 = %.2f ± %.2f um, kappa = %.3f"
              % (u[j], d50[j] * 1e6, dd50[j] * 1e6, k[j].mean()))
    return u, d50, dd50


if __name__ == "__main__":
    main()
