#!/usr/bin/python3
"""Plot fe2_biaxial runs: the stress-strain curve, the volumetric strain and
the Newton iterations per step (the paper's Fig. 6), one or several runs.

  plot_fe2_biaxial.py results/fe2_biaxial
  plot_fe2_biaxial.py run_demqo run_uko --labels DEMQO UKO -o operators.png

Each argument is an -output_dir of fe2_biaxial (its biaxial.csv, and
timing.csv when present).  Panels: deviator q = sigma_1 - sigma_3 against
the axial strain (with the single-point reference when the run has one),
volumetric strain against axial strain, Newton iterations per step (filled:
accepted increments; hatched: iterations of rejected attempts, i.e. step
halvings) with the post-peak steps marked, and the wall time per step.  The
PNG is written to a temporary name and renamed.
"""
import argparse
import csv
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_table(path):
    """{name: [values]} of a Talus CSV ("name [unit]" header cells)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))  # past the provenance lines
    names = [c.split("[")[0].strip() for c in rows[0]]
    cols = {n: [] for n in names}
    for r in rows[1:]:
        for n, v in zip(names, r):
            cols[n].append(float(v) if v.strip() else math.nan)
    return cols


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", help="fe2_biaxial output folders")
    ap.add_argument("--labels", nargs="*", help="legend labels (default: the folder names)")
    ap.add_argument("-o", "--output", help="PNG path (default: <first run>/biaxial.png)")
    a = ap.parse_args()
    labels = a.labels if a.labels else [os.path.basename(os.path.normpath(r)) for r in a.runs]
    if len(labels) != len(a.runs):
        ap.error(f"{len(labels)} labels for {len(a.runs)} runs")
    fig, ax = plt.subplots(2, 2, figsize=(11, 8))
    width = 0.8 / len(a.runs)
    for k, (run, label) in enumerate(zip(a.runs, labels)):
        t = read_table(os.path.join(run, "biaxial.csv"))
        eps = [100.0 * e for e in t["axial_strain"]]
        q = [v / 1e3 for v in t["q"]]
        ax[0][0].plot(eps, q, "-o", ms=3, label=label)
        ref = [v / 1e3 for v in t.get("q_reference", [])]
        if ref and not all(math.isnan(v) for v in ref):
            ax[0][0].plot(eps, ref, "k--", lw=1, label=f"{label}: one material point")
        ax[0][1].plot(eps, [100.0 * v for v in t["volumetric_strain"]], "-o", ms=3, label=label)
        steps = t["step"]
        x = [s + (k - (len(a.runs) - 1) / 2) * width for s in steps]
        ax[1][0].bar(x, t["iterations"], width, label=label)
        ax[1][0].bar(x, t["failed_iterations"], width, bottom=t["iterations"], hatch="//", fill=False)
        post = [s for s, p in zip(steps, t["post_peak"]) if p > 0]
        if post and k == 0:
            ax[1][0].axvspan(min(post) - 0.5, max(post) + 0.5, color="0.9", zorder=0, label="post-peak")
        timing = os.path.join(run, "timing.csv")
        if os.path.exists(timing):
            tt = read_table(timing)
            ax[1][1].semilogy(tt["step"], tt["wall"], "-o", ms=3, label=f"{label}: step")
            ax[1][1].semilogy(tt["step"], [max(v, 1e-9) for v in tt["t_points_wall"]], "--", label=f"{label}: Gauss points")
    ax[0][0].set(xlabel="axial strain [%]", ylabel="q = sigma_1 - sigma_3 [kPa]", title="stress-strain")
    ax[0][1].set(xlabel="axial strain [%]", ylabel="volumetric strain [%] (dilation +)", title="volume")
    ax[1][0].set(xlabel="load step", ylabel="Newton iterations", title="iterations per step (hatched: rejected)")
    ax[1][1].set(xlabel="load step", ylabel="wall time [s]", title="time per step")
    for row in ax:
        for p in row:
            p.grid(True, alpha=0.3)
            p.legend(fontsize=8)
    fig.tight_layout()
    out = a.output or os.path.join(a.runs[0], "biaxial.png")
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, out)
    print(out)


if __name__ == "__main__":
    main()
