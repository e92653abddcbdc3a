#!/usr/bin/python3
"""Plots of the cantilever_fem driver: large-deflection load path against the
elastica, and free vibration (tip deflection and energy drift).

usage: plot_cantilever_fem.py OUTPUT_DIR   (reads large.csv and vibration.csv,
writes cantilever_fem.png there)"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))  # past the provenance lines
    head, body = rows[0], rows[1:]
    return {h: [float(r[i]) for r in body] for i, h in enumerate(head)}


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    fig, (ax1, ax2, ax3) = plt.subplots(1, 3, figsize=(15, 4.2))
    large = os.path.join(out, "large.csv")
    if os.path.exists(large):
        d = read(large)
        p = d["load_parameter"]
        ax1.plot(p, d["tip_w [m]"], "o-", label="Talus tip deflection w")
        ax1.plot(p, d["elastica_w [m]"], "k--", label="elastica w")
        ax1.plot(p, d["tip_v [m]"], "s-", label="Talus tip shortening v")
        ax1.plot(p, d["elastica_v [m]"], "k:", label="elastica v")
        ax1.set_xlabel("load parameter P L² / (E I)")
        ax1.set_ylabel("tip displacement [m]")
        ax1.set_title("large deflection")
        ax1.legend(fontsize=8)
    vib = os.path.join(out, "vibration.csv")
    if os.path.exists(vib):
        d = read(vib)
        t = d["t [s]"]
        ax2.plot(t, d["tip_w [m]"])
        ax2.set_xlabel("t [s]")
        ax2.set_ylabel("tip deflection [m]")
        ax2.set_title("free vibration (Newmark 1/4, 1/2)")
        e0 = d["total [J]"][0]
        ax3.plot(t, [abs(e - e0) / abs(e0) + 1e-17 for e in d["total [J]"]])
        ax3.set_yscale("log")
        ax3.set_xlabel("t [s]")
        ax3.set_ylabel("|E(t) - E(0)| / E(0)")
        ax3.set_title("total energy drift")
    fig.tight_layout()
    target = os.path.join(out, "cantilever_fem.png")
    tmp = os.path.join(out, ".cantilever_fem.png.tmp")
    fig.savefig(tmp, dpi=110, format="png")
    os.replace(tmp, target)
    print("wrote", target)


if __name__ == "__main__":
    main()
