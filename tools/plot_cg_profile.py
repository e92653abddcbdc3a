#!/usr/bin/python3
"""Plots the CG profile written by Drivers/cg_fields (profile.csv) to PNG:
solid fraction, vertical stress against the weight of the material above,
pressure and the kinetic part, each against height z.

usage: tools/plot_cg_profile.py [results/cg_fields/profile.csv] [-o profile.png]
"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_profile(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))  # past the provenance lines
    if len(rows) < 2:
        sys.exit(f"{path}: no data rows")
    names = [h.split(" [")[0] for h in rows[0]]
    cols = {n: [] for n in names}
    for r in rows[1:]:
        for n, v in zip(names, r):
            cols[n].append(float(v))
    missing = {"z", "solid_fraction", "szz", "pressure", "weight_above"} - set(cols)
    if missing:
        sys.exit(f"{path}: columns {sorted(missing)} missing")
    return cols


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("profile", nargs="?", default="results/cg_fields/profile.csv")
    ap.add_argument("-o", "--output", default=None, help="PNG file (default: next to the CSV)")
    a = ap.parse_args()
    p = read_profile(a.profile)
    out = a.output or os.path.join(os.path.dirname(a.profile) or ".", "profile.png")
    z = p["z"]
    fig, ax = plt.subplots(1, 3, figsize=(12, 4.5), sharey=True)
    ax[0].plot(p["solid_fraction"], z, "k-")
    ax[0].set_xlabel("solid fraction")
    ax[0].set_ylabel("z [m]")
    ax[1].plot([-s for s in p["szz"]], z, "b-", label=r"$-\sigma_{zz}$ (CG)")
    ax[1].plot(p["weight_above"], z, "r--", label=r"$g\int_z^\infty \rho\,dz'$")
    ax[1].set_xlabel("stress [Pa]")
    ax[1].legend()
    ax[2].plot(p["pressure"], z, "g-", label="pressure")
    if "szz_kinetic" in p:
        ax[2].plot([-s for s in p["szz_kinetic"]], z, "m:", label=r"$-\sigma^k_{zz}$")
    ax[2].set_xlabel("stress [Pa]")
    ax[2].legend()
    for a_ in ax:
        a_.grid(alpha=0.3)
    fig.suptitle(os.path.basename(os.path.dirname(os.path.abspath(a.profile))) + ": coarse-grained profile")
    fig.tight_layout()
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, out)
    print(out)


if __name__ == "__main__":
    main()
