#!/usr/bin/python3
"""Plots of a wave_volume_coupling or wave_full_dem run (Cheng et al. 2022,
CMAME 403, 115651, doi:10.1016/j.cma.2022.115651, Figs. 19-21).

  plot_wave.py results/wave_volume_coupling   (or results/wave_full_dem)
      energies.png  weighted energies of the sub-models and their total
                    against the full-DEM reference (Fig. 20 d-f)
      momentum.png  weighted y momentum of each sub-model and the total
                    against the reference (Fig. 20 b-c)
      profiles.png  v_y along the bar at the snapshot times, coupled and
                    full DEM (Fig. 19)
  plot_wave.py --sweep table.md -o dissipation.png [--paper]
      dissipated fraction, profile error and wall time against the CG
      width from the Markdown table of tools/sweep_wave.sh, one line per
      case/excitation/variant (Fig. 21; --paper adds the paper's 1P pulse)

PNGs are written to a temporary name and renamed.
"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_csv(path):
    """Columns by name from a table of the drivers' writer: '#' lines are
    comments, the header reads "name [unit],..."; the units are returned
    beside the columns (cols, units)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))  # past the provenance lines
    if len(rows) < 2:
        sys.exit(f"{path}: no data rows")
    head, units = [], {}
    for h in rows[0]:
        name, _, unit = h.strip().partition(" [")
        head.append(name)
        units[name] = unit.rstrip("]")
    cols = {h: [] for h in head}
    for r in rows[1:]:
        for h, v in zip(head, r):
            cols[h].append(float(v))
    return cols, units


def save(fig, path):
    tmp = os.path.join(os.path.dirname(path) or ".", "." + os.path.basename(path) + ".tmp.png")
    fig.savefig(tmp, dpi=120, bbox_inches="tight")
    plt.close(fig)
    os.replace(tmp, path)
    print(path)


def plot_run(folder):
    e, _ = read_csv(os.path.join(folder, "energies.csv"))
    t = e["t"]
    full_dem = "kin_fem" not in e  # a wave_full_dem folder: the DEM bar alone
    fig, ax = plt.subplots(figsize=(7, 4))
    for key, label in [("kin_dem", "DEM kinetic" + ("" if full_dem else " (w)")),
                       ("pot_dem", "DEM potential" + ("" if full_dem else " (w)")),
                       ("kin_fem", "FEM kinetic (1-w)"), ("pot_fem", "FEM potential (1-w)"),
                       ("pot_coupling", "coupling spring"), ("total", "total"), ("ref_total", "full DEM")]:
        if key in e and max(abs(v) for v in e[key]) > 0:
            ax.plot(t, e[key], "--" if key == "ref_total" else "-", label=label)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("energy [J]")
    ax.legend(fontsize=8)
    save(fig, os.path.join(folder, "energies.png"))

    fig, ax = plt.subplots(figsize=(7, 4))
    for key, label in [("mom_dem", "DEM" if full_dem else "DEM (w)"), ("mom_fem", "FEM (1-w)"), ("mom_total", "total"),
                       ("ref_mom", "full DEM")]:
        if key in e:
            ax.plot(t, e[key], "--" if key == "ref_mom" else "-", label=label)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("y momentum [kg m/s]")
    ax.legend(fontsize=8)
    save(fig, os.path.join(folder, "momentum.png"))

    p, _ = read_csv(os.path.join(folder, "profiles.csv"))
    fig, ax = plt.subplots(figsize=(8, 4))
    times = sorted(set(p["t"]))
    for k, ts in enumerate(times):
        idx = [i for i, v in enumerate(p["t"]) if v == ts]
        y = [p["y"][i] for i in idx]
        ax.plot(y, [p["vy"][i] for i in idx], "-", color=f"C{k}",
                label=f"{'full DEM' if full_dem else 'coupled'} t = {ts:.3g} s")
        if "vy_ref" in p:
            ax.plot(y, [p["vy_ref"][i] for i in idx], "o", ms=3, color=f"C{k}", label=f"full DEM t = {ts:.3g} s")
    if not full_dem:
        ax.axvspan(8.0, 12.0, color="0.9", zorder=0)  # the overlap of the default scene
    ax.set_xlabel("y [m]")
    ax.set_ylabel("v_y [m/s]")
    ax.legend(fontsize=8)
    save(fig, os.path.join(folder, "profiles.png"))


# Cheng et al. 2022, §6.2.2, Fig. 21: 1P pulse, dissipated % against c / dX (no
# further gain at 2 and 2.5 dX).
PAPER_1P_PULSE = [(0.0, 33.5), (1.5, 29.5), (2.0, 29.5), (2.5, 29.5)]


def plot_sweep(table, out, paper=False):
    """Three panels from the rows of tools/sweep_wave.sh: dissipated energy,
    profile error (solid: particles as they are; dashed, where the table
    has it: the weighted Arlequin field) and wall time of the coupled run
    against the CG width, one line per case/excitation/variant."""
    lines = {}
    with open(table) as f:
        for line in f:
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if len(cells) < 6 or cells[0] in ("case", "---") or cells[0].startswith("-") or cells[4].startswith("failed"):
                continue
            case, exc, var, c = cells[0], cells[1], cells[2], cells[3]
            try:
                cval = float(c[:-1]) if c.endswith("h") else float(c) / 0.4
                dis = 100.0 * float(cells[4])
                err = float(cells[5])
                wall = float(cells[8]) if len(cells) > 8 and cells[8] else float("nan")
                errw = float(cells[10]) if len(cells) > 10 and cells[10] else float("nan")
            except ValueError:
                continue
            # "paper" is the default formulation: left out of the label, so
            # that it is not read as the paper's data
            label = f"{case} {exc}" + ("" if var == "paper" else f", {var}")
            lines.setdefault(label, []).append((cval, dis, err, wall, errw))
    if not lines:
        sys.exit(f"{table}: no rows")
    fig, axs = plt.subplots(1, 3, figsize=(15, 4.2))
    for label, pts in sorted(lines.items()):
        pts.sort()
        cs = [p[0] for p in pts]
        for k, ax in enumerate(axs):
            line, = ax.plot(cs, [p[k + 1] for p in pts], "o-", label=label)
        if any(p[4] == p[4] for p in pts):  # weighted (Arlequin) profile error, where measured
            axs[1].plot([p[0] for p in pts if p[4] == p[4]], [p[4] for p in pts if p[4] == p[4]], "s--",
                        color=line.get_color(), mfc="none", label=label + ", weighted field")
    if paper:
        axs[0].plot([p[0] for p in PAPER_1P_PULSE], [p[1] for p in PAPER_1P_PULSE], "k*--", ms=10,
                    label="paper 1P pulse (Fig. 21)")
    axs[0].set_ylabel("dissipated energy [%]")
    axs[1].set_ylabel("profile error (relative L2 against full DEM)")
    axs[2].set_ylabel("wall time of the coupled run [s]")
    axs[2].set_yscale("log")
    for ax in axs:
        ax.set_xlabel("CG width c / ΔX")
        ax.grid(alpha=0.3)
    axs[0].legend(fontsize=7)
    if any(len(h.get_label()) and "weighted" in h.get_label() for h in axs[1].get_lines()):
        axs[1].legend(fontsize=7)
    save(fig, out)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("folder", nargs="?", help="output folder of wave_volume_coupling or wave_full_dem")
    ap.add_argument("--sweep", help="Markdown table of tools/sweep_wave.sh")
    ap.add_argument("-o", default="dissipation.png", help="PNG of --sweep")
    ap.add_argument("--paper", action="store_true", help="overlay the paper's 1P pulse dissipation (Fig. 21)")
    a = ap.parse_args()
    if a.sweep:
        plot_sweep(a.sweep, a.o, a.paper)
    if a.folder:
        plot_run(a.folder)
    if not a.sweep and not a.folder:
        ap.error("give an output folder or --sweep")


if __name__ == "__main__":
    main()
