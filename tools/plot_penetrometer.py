#!/usr/bin/python3
"""Plots a penetrometer run: resistance against depth for each CG width,
side by side (c = 0 left, c > 0 right) with the run's wall time in each
title, and the energy balance of every run below.

usage: /usr/bin/python3 tools/plot_penetrometer.py RESULTS_DIR [OUT.png] [--log PENETROMETER_OUTPUT]

RESULTS_DIR is the driver's -output_dir (force_depth_c<k>.csv); the widths
and wall times are read from the driver's printed output (--log FILE: the
lines 'run k: c = ...' and 'run k (c = ...): ... wall T s'), or from
RESULTS_DIR/run.log when it exists."""
import csv
import glob
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def read_table(path):
    with open(path) as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))  # past the provenance lines
    head = [h.split(" ")[0].split("[")[0] for h in rows[0]]
    cols = {h: [] for h in head}
    for r in rows[1:]:
        for h, v in zip(head, r):
            cols[h].append(float(v))
    return cols


def read_log(path):
    widths, walls = {}, {}
    if not path or not os.path.exists(path):
        return widths, walls
    for line in open(path):
        m = re.match(r"run (\d+) \(c = ([0-9.eE+-]+) d\):.* wall ([0-9.eE+-]+) s", line)
        if m:
            widths[int(m.group(1))] = float(m.group(2))
            walls[int(m.group(1))] = float(m.group(3))
    return widths, walls


def main(argv):
    if len(argv) < 2:
        print(__doc__)
        return 2
    d = argv[1]
    out = argv[2] if len(argv) > 2 and not argv[2].startswith("--") else os.path.join(d, "penetrometer.png")
    log = None
    if "--log" in argv:
        log = argv[argv.index("--log") + 1]
    elif os.path.exists(os.path.join(d, "run.log")):
        log = os.path.join(d, "run.log")
    widths, walls = read_log(log)
    files = sorted(glob.glob(os.path.join(d, "force_depth_c*.csv")), key=lambda p: int(re.findall(r"c(\d+)", p)[-1]))
    if not files:
        print("no force_depth_c*.csv in", d)
        return 1
    n = len(files)
    fig, ax = plt.subplots(2, n, figsize=(5 * n, 7), squeeze=False, sharey="row")
    for k, path in enumerate(files):
        t = read_table(path)
        depth = [1e3 * x for x in t["depth"]]
        c = widths.get(k)
        title = "c = %s d" % (("%g" % c) if c is not None else "?")
        if k in walls:
            title += ", wall %.1f s" % walls[k]
        a = ax[0][k]
        a.plot(depth, t["force"], lw=0.8, label="grains on the cone")
        a.plot(depth, [-r for r in t["base_reaction"]], lw=0.8, alpha=0.7, label="drive (base reaction)")
        a.set_title(title)
        a.set_xlabel("apex depth (mm)")
        a.set_ylabel("resistance F_z (N)")
        a.axvline(0.0, color="k", lw=0.5)
        a.legend(fontsize=8)
        b = ax[1][k]
        w = t["work_drive"]
        b.plot(t["time"], w, label="work of the drive")
        b.plot(t["time"], t["balance"], label="E - E0 (balance)")
        b.plot(t["time"], t["dissipated"], label="dissipated (DEM)")
        b.set_xlabel("time (s)")
        b.set_ylabel("energy (J)")
        b.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print("wrote", out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
