#!/usr/bin/python3
"""Accuracy against time for the S1 sweep (tools/sweep_particle_cantilever.sh).

usage: plot_sweep_particle_cantilever.py <sweep dir> [-o out.png]

Reads <sweep dir>/sweep.csv and draws two panels: the time-averaged position
error err_avg (m) and the largest total energy E_max (J) against the CPU
seconds of each run, one marker per stepping choice (implicit Newmark or
explicit central difference; 1, 5 or 20 DEM steps per FEM step), the CG width
written beside each point.  Refused runs (a FEM step beyond the explicit
critical one) are listed under the plot.  Written atomically.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "-help", "--help"):
        print(__doc__)
        return 0 if len(argv) >= 2 else 1
    folder = argv[1]
    out = os.path.join(folder, "sweep.png")
    if "-o" in argv:
        out = argv[argv.index("-o") + 1]
    path = os.path.join(folder, "sweep.csv")
    try:
        rows = list(csv.DictReader(open(path)))
    except OSError as e:
        print(f"plot_sweep_particle_cantilever: cannot read {path}: {e}", file=sys.stderr)
        return 1
    if not rows:
        print(f"plot_sweep_particle_cantilever: {path} holds no runs", file=sys.stderr)
        return 1
    markers = {"newmark": "o", "central_difference": "s"}
    colours = {"1": "tab:blue", "2": "tab:purple", "5": "tab:orange", "20": "tab:green"}
    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    refused, seen = [], set()
    for r in rows:
        if not r["cpu"]:
            refused.append(r["c"])
            continue
        key = (r["fem"], r["substeps"])
        label = None if key in seen else f"{r['fem']}, {r['substeps']} DEM steps per FEM step"
        seen.add(key)
        cpu = float(r["cpu"])
        for ax, q in zip(axes, ("err_avg", "E_max")):
            y = float(r[q])
            ax.scatter(cpu, y, marker=markers.get(r["fem"], "x"), color=colours.get(r["substeps"], "k"),
                       label=label)
            ax.annotate(r["c"], (cpu, y), textcoords="offset points", xytext=(4, 3), fontsize=8)
    axes[0].set_ylabel("err_avg (m), time-averaged error against the analytic path")
    axes[1].set_ylabel("E_max (J), largest total energy (start 0.87 J)")
    for ax in axes:
        ax.set_xlabel("CPU time of the run (s, one thread)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].axhline(0.01, color="grey", ls="--", lw=0.8)
    axes[0].legend(fontsize=7, loc="upper right")
    fig.suptitle("S1 particle-cantilever: accuracy against cost (labels: CG width c)")
    if refused:
        fig.text(0.01, 0.01, f"{len(refused)} runs not finished (refused or stopped as unstable): see sweep.csv", fontsize=8)
    fig.tight_layout(rect=(0, 0.04, 1, 0.95))
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, out)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
