"""The equation of state of hard spheres with error bars, against Carnahan-Starling.

At each packing fraction eta, R replicas (independent seeds 1 ... R, run side by side in Python
threads: mote releases the GIL) of N spheres in a periodic box (mote.HardSpheres) each measure
the compressibility factor Z = P/(rho kT) with `pressure`; the mean and its standard error over
the replicas are plotted with matplotlib against Z_CS = (1 + eta + eta^2 - eta^3) / (1 - eta)^3.
(The same replicas as the script `ensemble R` ... `end` runs: examples/eos-sweep.mote.)

    python3 eos_sweep.py [--quick] [--out DIR]      (writes DIR/eos.dat and DIR/eos.png)
"""
import argparse
import os
from concurrent.futures import ThreadPoolExecutor

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import mote


def carnahan_starling(eta):
    return (1 + eta + eta**2 - eta**3) / (1 - eta) ** 3


def replica(eta, N, K, seed):
    """Z of one replica: N spheres at eta, 200 collisions per particle to forget the lattice,
    then the pressure over K more."""
    hs = mote.HardSpheres(N=N, eta=eta, seed=seed)
    hs.step(200)
    return hs.pressure(K)["Z"][0]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a short run (for the tests)")
    ap.add_argument("--out", default="out/eos_sweep")
    a = ap.parse_args(argv)
    out = os.path.abspath(a.out)
    os.makedirs(out, exist_ok=True)
    R, N, K = (2, 256, 50) if a.quick else (8, 864, 400)
    eta = np.round(np.arange(0.1, 0.451, 0.05), 2)
    with ThreadPoolExecutor(max_workers=os.cpu_count()) as pool:
        zs = np.array([list(pool.map(lambda s, e=e: replica(e, N, K, s), range(1, R + 1)))
                       for e in eta])
    Z, dZ = zs.mean(axis=1), zs.std(axis=1, ddof=1) / np.sqrt(R)
    np.savetxt(os.path.join(out, "eos.dat"), np.column_stack([eta, Z, dZ]),
               header="eta Z Z_err  (N = %d, %d replicas, pressure over %d)" % (N, R, K))
    fine = np.linspace(0, 0.5, 200)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot(fine, carnahan_starling(fine), "k-", lw=1, label="Carnahan-Starling")
    ax.errorbar(eta, Z, yerr=dZ, fmt="o", color="C0", capsize=3,
                label="mote, N = %d, %d replicas" % (N, R))
    ax.set_xlabel("packing fraction $\\eta$")
    ax.set_ylabel("$Z = P / \\rho kT$")
    ax.set_xlim(0, 0.5)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "eos.png"), dpi=120)
    print("eta    Z            Z_CS     (Z - Z_CS)/error")
    for e, z, dz in zip(eta, Z, dZ):
        cs = carnahan_starling(e)
        print("%.2f  %.4f ± %.4f  %.4f  %+.1f" % (e, z, dz, cs, (z - cs) / dz if dz > 0 else 0))
    return eta, Z, dZ


if __name__ == "__main__":
    main()
