#!/usr/bin/python3
"""Plots a tutorial's CSV table (the library's time-series format: a header
"name [unit],...", then rows): every column, or the ones named, against the
first, one panel per unit so that metres and newtons never share an axis.

    /usr/bin/python3 docs/tutorial/plot.py out/collision.csv [v1 v2 ...]

Writes out/collision.png beside the table (Debian: python3-matplotlib)."""
import csv
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def read(path):
    with open(path) as f:
        rows = [r for r in csv.reader(line for line in f if not line.startswith("#"))]
    names, units = [], []
    for h in rows[0]:
        m = re.match(r"\s*(.*?)\s*(?:\[(.*)\])?\s*$", h)
        names.append(m.group(1))
        units.append(m.group(2) or "1")
    cols = list(zip(*[[float(v) for v in r] for r in rows[1:]]))
    return names, units, cols


def main(argv):
    if len(argv) < 2:
        sys.exit(__doc__)
    names, units, cols = read(argv[1])
    wanted = argv[2:] or names[1:]
    for w in wanted:
        if w not in names:
            sys.exit("no column %r in %s (columns: %s)" % (w, argv[1], ", ".join(names)))
    panels = []
    for w in wanted:
        u = units[names.index(w)]
        if u not in panels:
            panels.append(u)
    fig, axes = plt.subplots(len(panels), 1, sharex=True, figsize=(7, 2.6 * len(panels)), squeeze=False)
    for w in wanted:
        k = names.index(w)
        ax = axes[panels.index(units[k])][0]
        ax.plot(cols[0], cols[k], label=w)
        ax.set_ylabel("[%s]" % units[k])
        ax.legend(loc="best", fontsize="small")
    axes[-1][0].set_xlabel("%s [%s]" % (names[0], units[0]))
    fig.tight_layout()
    out = re.sub(r"\.csv$", "", argv[1]) + ".png"
    fig.savefig(out, dpi=120)
    print(out)


if __name__ == "__main__":
    main(sys.argv)
