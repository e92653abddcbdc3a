#!/usr/bin/python3
"""Plot columns of a Talus time-series CSV file into a PNG.

The CSV is the one a TlTimeSeries writes: '#' comment lines, a header line
of "name [unit]" cells (just "name" when dimensionless), then one row per
line.  Columns are chosen by name.  Columns of one unit share a panel whose
axis is labelled with that unit; each further unit gets a panel of its own
below, on the same x axis (Pa, J and 1/s are never drawn on one axis).

  plot_timeseries.py results/run/energy.csv -y kinetic_energy elastic_energy --logy
  plot_timeseries.py energy.csv -x time -y total_energy -o energy.png

Without -y every column but the x column is plotted; without -o the PNG is
written next to the CSV (energy.csv -> energy.png).  --describe prints each
panel as "panel UNIT COLUMN ..." (for tests).  The PNG is written to a
temporary name and renamed, like every Talus output file.
"""
import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def parse_header(cells):
    """[(name, unit)] from 'name [unit]' cells."""
    out = []
    for cell in cells:
        cell = cell.strip()
        if cell.endswith("]") and "[" in cell:
            name, unit = cell[:-1].split("[", 1)
            out.append((name.strip(), unit.strip()))
        else:
            out.append((cell, ""))
    return out


def read_table(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))  # past the provenance lines
    if not rows:
        raise SystemExit(f"error: {path} is empty (no header line)")
    header = parse_header(rows[0])
    data = [[] for _ in header]
    for lineno, row in enumerate(rows[1:], start=2):
        if not row:
            continue
        if len(row) != len(header):
            raise SystemExit(f"error: {path} line {lineno} has {len(row)} values, the header has {len(header)}")
        for j, value in enumerate(row):
            try:
                data[j].append(float(value))
            except ValueError:
                raise SystemExit(f"error: {path} line {lineno}: column '{header[j][0]}' value '{value}' is not a number")
    return header, data


def column(header, name):
    for j, (n, _) in enumerate(header):
        if n == name:
            return j
    known = ", ".join(n for n, _ in header)
    raise SystemExit(f"error: no column '{name}'; the columns are: {known}")


def label(name, unit):
    return f"{name} [{unit}]" if unit else name


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("csv", help="time-series CSV file")
    p.add_argument("-x", help="column on the x axis (default: the first)")
    p.add_argument("-y", nargs="+", help="columns to plot (default: all others)")
    p.add_argument("-o", "--output", help="PNG to write (default: the CSV's name with .png)")
    p.add_argument("--logx", action="store_true", help="logarithmic x axis")
    p.add_argument("--logy", action="store_true", help="logarithmic y axis (plots |value|; zeros are left out)")
    p.add_argument("--title", help="plot title (default: the CSV's file name)")
    p.add_argument("--dpi", type=int, default=150, help="resolution of the PNG (default 150)")
    p.add_argument("--describe", action="store_true", help="print the panels (unit and columns)")
    a = p.parse_args(argv)

    header, data = read_table(a.csv)
    jx = column(header, a.x) if a.x else 0
    ys = [column(header, n) for n in a.y] if a.y else [j for j in range(len(header)) if j != jx]
    if not ys:
        raise SystemExit("error: nothing to plot: the file has a single column")
    if not data[jx]:
        raise SystemExit(f"error: {a.csv} has a header but no rows")

    # one panel per unit, in the order the units first appear
    panels = []
    for j in ys:
        unit = header[j][1]
        for pu, cols in panels:
            if pu == unit:
                cols.append(j)
                break
        else:
            panels.append((unit, [j]))
    fig, axes = plt.subplots(len(panels), 1, sharex=True, squeeze=False,
                             figsize=(7, 2.2 + 2.3 * len(panels)))
    for (unit, cols), ax in zip(panels, axes[:, 0]):
        for j in cols:
            x, y = data[jx], data[j]
            if a.logy:
                pairs = [(u, abs(v)) for u, v in zip(x, y) if v != 0 and math.isfinite(v)]
                x, y = [u for u, _ in pairs], [v for _, v in pairs]
            ax.plot(x, y, label=header[j][0])
        if len(cols) == 1:
            ax.set_ylabel(label(*header[cols[0]]))
        else:
            ax.set_ylabel(f"[{unit}]" if unit else "(dimensionless)")
            ax.legend(fontsize=8)
        if a.logx:
            ax.set_xscale("log")
        if a.logy:
            ax.set_yscale("log")
        ax.grid(True, alpha=0.3)
        if a.describe:
            print("panel", f"[{unit}]" if unit else "[]", *[header[j][0] for j in cols])
    axes[-1, 0].set_xlabel(label(*header[jx]))
    axes[0, 0].set_title(a.title if a.title is not None else os.path.basename(a.csv))
    fig.tight_layout()

    out = a.output or os.path.splitext(a.csv)[0] + ".png"
    folder = os.path.dirname(os.path.abspath(out))
    tmp = os.path.join(folder, f".{os.path.basename(out)}.{os.getpid()}.tmp")
    try:
        fig.savefig(tmp, dpi=a.dpi, format="png")
        with open(tmp, "rb") as f:
            os.fsync(f.fileno())
        os.replace(tmp, out)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
