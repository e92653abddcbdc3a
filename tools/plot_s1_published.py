#!/usr/bin/python3
"""Total energy of S1 runs against the authors' published runs (cf. Fig. 17).

usage: plot_s1_published.py <Oomph-Mercury checkout> out.png LABEL=RUN_DIR [LABEL=RUN_DIR ...]

Each RUN_DIR is a particle_cantilever output folder (its energy.csv); its
label must start with the CG width it was run at (0, 2d, 4d, 6d or 10d,
e.g. "10d lagged walls"), so that it is drawn in the panel of that width
beside the published run of the same width (tools/s1_published_runs.py
reads the same files).  One panel per width, total energy on a log scale.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from s1_published_runs import CASES, J_SCALE, read_table  # noqa: E402


def published_energy(root, sub):
    folder = os.path.join(root, "SingleSphere", sub)
    ene = read_table(os.path.join(folder, "SingleSphere.ene"), 1)
    trace = read_table(os.path.join(folder, "Trace.dat"), 0)
    n = min(len(ene), len(trace))
    t = [ene[k][0] * 1e-3 for k in range(n)]
    e = [(ene[k][8] - ene[0][8] + ene[k][9] + ene[k][10] + ene[k][11] + trace[k][12] + trace[k][13]) * J_SCALE
         for k in range(n)]
    return t, e


def our_energy(folder):
    t, e = [], []
    with open(os.path.join(folder, "energy.csv")) as f:
        for row in csv.DictReader(f):
            t.append(float(row["t [s]"]))
            e.append(float(row["total [J]"]))
    return t, e


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    root, out = sys.argv[1], sys.argv[2]
    runs = [a.rsplit("=", 1) for a in sys.argv[3:]]
    widths = [c for _, c in CASES if any(label.split()[0] == c for label, _ in runs)]
    if not widths:
        sys.exit("plot_s1_published: no run label starts with a width of " + ", ".join(c for _, c in CASES))
    fig, axes = plt.subplots(1, len(widths), figsize=(4.2 * len(widths), 3.6), squeeze=False)
    for ax, c in zip(axes[0], widths):
        sub = dict((w, s) for s, w in CASES)[c]
        t, e = published_energy(root, sub)
        ax.semilogy(t, e, color="0.3", lw=2.5, label="published run")
        for label, folder in runs:
            if label.split()[0] != c:
                continue
            tt, ee = our_energy(folder)
            ax.semilogy(tt, [max(v, 1e-3) for v in ee], lw=1.2, label=label)
        ax.set_title(f"c = {c}")
        ax.set_xlabel("t (s)")
        ax.set_xlim(0, 40)
        ax.grid(True, which="major", alpha=0.3)
    axes[0][0].set_ylabel("total energy (J)")
    for ax in axes[0]:
        ax.legend(fontsize=7)
    fig.tight_layout()
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, out)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
