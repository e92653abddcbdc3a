#!/usr/bin/python3
"""Plots of the particle_cantilever driver (S1) in the manner of Cheng et al.
2022 (CMAME 403, 115651, doi:10.1016/j.cma.2022.115651), Figs. 12-17: x-y and
y-z trajectories of both particles against the analytic path, the error
z - z_ref along y, and the energies.  One run: every term of the total
(DEM kinetic and elastic, the particles' gravitational energy relative to the
start, FEM kinetic and strain), each in its own colour, and the total in
black, on a linear scale (the gravitational term is negative).  With several
run folders the trajectories and totals are overlaid, the totals on a log
scale (Figs. 13-17: one curve per CG width).  With a
sweep folder holding sweep.csv it also plots err_avg and E_max against the
wall time (the accuracy-versus-time table).

usage: plot_particle_cantilever.py RUN_DIR [RUN_DIR ...] [-o OUT.png] [--describe]
       plot_particle_cantilever.py --sweep SWEEP_DIR
(reads trajectory.csv, energy.csv, reference_path.csv of each run; writes
particle_cantilever.png in the first run folder unless -o is given; --describe
also prints each line of the energy panel as "energy-line LABEL COLOUR")"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))  # past the provenance lines
    head = [h.split(" [")[0] for h in rows[0]]
    body = rows[1:]
    return {h: [float(r[i]) for r in body] for i, h in enumerate(head)}


def label(run):
    return os.path.basename(os.path.normpath(run))


def plot_runs(runs, out, describe=False):
    fig, ax = plt.subplots(2, 2, figsize=(13, 9))
    (axy, ayz), (aerr, aen) = ax
    ref = read(os.path.join(runs[0], "reference_path.csv"))
    axy.plot(ref["y"], ref["x_ref"], "k--", lw=1, label="analytic")
    axy.plot(ref["y"], [-x for x in ref["x_ref"]], "k--", lw=1)
    ayz.plot(ref["y"], ref["z_ref"], "k--", lw=1, label="analytic")
    for run in runs:
        tr = read(os.path.join(run, "trajectory.csv"))
        en = read(os.path.join(run, "energy.csv"))
        name = label(run)
        line = axy.plot(tr["y1"], tr["x1"], lw=1, label=name)[0]
        axy.plot(tr["y2"], tr["x2"], lw=1, color=line.get_color())
        ayz.plot(tr["y1"], tr["z1"], lw=1, color=line.get_color(), label=name)
        aerr.plot(tr["y1"], [z - r for z, r in zip(tr["z1"], tr["z_ref1"])], lw=1, color=line.get_color(), label=name)
        if len(runs) == 1:
            # the terms whose sum is the total, each in a colour of its own
            for k, (key, what) in enumerate((("dem_kinetic", "DEM kinetic"), ("dem_elastic", "DEM elastic"),
                                             ("gravitational", "gravitational (from the start)"),
                                             ("fem_kinetic", "FEM kinetic"), ("fem_strain", "FEM strain"))):
                aen.plot(en["t"], en[key], lw=0.9, color=f"C{k + 1}", label=what)
            aen.plot(en["t"], en["total"], lw=1.6, color="k", label="total")
        else:
            aen.semilogy(en["t"], [max(abs(e), 1e-6) for e in en["total"]], lw=1.2, color=line.get_color(),
                         label=name + " total")
    axy.set(xlabel="y (m)", ylabel="x (m)", title="x-y trajectories (Fig. 12a/13a)")
    ayz.set(xlabel="y (m)", ylabel="z (m)", title="y-z trajectory of particle 1 (Fig. 12b)")
    aerr.set(xlabel="y (m)", ylabel="z - z_ref (m)", title="error along y (Fig. 13b)")
    aen.set(xlabel="t (s)", ylabel="energy (J)",
            title="energy terms and total (Figs. 16-17)" if len(runs) == 1 else "total energy, log scale (Figs. 16-17)")
    for a in (axy, ayz, aerr, aen):
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    fig.tight_layout()
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, out)
    if describe:
        import matplotlib.colors as mcolors
        for ln in aen.get_lines():
            print("energy-line", ln.get_label().replace(" ", "_"), mcolors.to_hex(ln.get_color()))
    print(out)


def plot_sweep(folder):
    rows = list(csv.DictReader(open(os.path.join(folder, "sweep.csv"))))
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4.5))
    for r in rows:
        if r["err_avg"] in ("failed", "", "nan"):
            continue
        name = "c=%s %s k=%s" % (r["c"], "NM" if r["fem"] == "newmark" else "CD", r["substeps"])
        a1.loglog(float(r["wall"]), float(r["err_avg"]), "o")
        a1.annotate(name, (float(r["wall"]), float(r["err_avg"])), fontsize=6)
        a2.loglog(float(r["wall"]), abs(float(r["E_max"])), "o")
        a2.annotate(name, (float(r["wall"]), abs(float(r["E_max"]))), fontsize=6)
    a1.set(xlabel="wall time (s)", ylabel="err_avg (m)", title="accuracy versus time (Fig. 15)")
    a2.set(xlabel="wall time (s)", ylabel="E_max (J)", title="largest total energy (Fig. 17)")
    for a in (a1, a2):
        a.grid(alpha=0.3, which="both")
    fig.tight_layout()
    out = os.path.join(folder, "sweep.png")
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, out)
    print(out)


def main():
    args = sys.argv[1:]
    if not args:
        sys.exit(__doc__)
    if args[0] == "--sweep":
        if len(args) != 2:
            sys.exit(__doc__)
        plot_sweep(args[1])
        return
    out = None
    describe = "--describe" in args
    args = [a for a in args if a != "--describe"]
    if "-o" in args:
        i = args.index("-o")
        out = args[i + 1]
        del args[i : i + 2]
    plot_runs(args, out or os.path.join(args[0], "particle_cantilever.png"), describe)


if __name__ == "__main__":
    main()
