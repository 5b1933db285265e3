"""The equation of state of hard spheres with error bars, against Carnahan-Starling.

At each packing fraction eta an ensemble of R replicas (independent seeds) of N spheres in a
periodic box measures the compressibility factor Z = P/(rho kT); the means and standard errors
come back as a table (mote.read_data) and are plotted with matplotlib against
Z_CS = (1 + eta + eta^2 - eta^3) / (1 - eta)^3.

    python3 eos_sweep.py [--quick] [--out DIR]      (writes DIR/eos.dat and DIR/eos.png)
"""
import argparse
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import mote

SCRIPT = """
output_dir ${out}
for eta from 0.1 to 0.45 step 0.05
    ensemble ${R} summary=eos.dat
        bulk ${N} ${eta}
        step 200
        pressure ${K} p_${eta}_${replica}.dat
    end
end
"""


def carnahan_starling(eta):
    return (1 + eta + eta**2 - eta**3) / (1 - eta) ** 3


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a short run (for the tests)")
    ap.add_argument("--out", default="out/eos_sweep")
    a = ap.parse_args(argv)
    out = os.path.abspath(a.out)
    R, N, K = (2, 256, 50) if a.quick else (8, 864, 400)
    mote.run(SCRIPT, out=out, R=R, N=N, K=K)
    table = mote.read_data(os.path.join(out, "eos.dat"))
    eta = table.column("eta")
    Z, dZ = table.column("pressure.Z"), table.column("pressure.Z_err")
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
