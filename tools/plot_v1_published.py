#!/usr/bin/python3
"""Dissipated fraction against CG width: the authors' published V1 runs beside ours.

usage: plot_v1_published.py docs/v1_published_runs.csv <sweep table.md> [...] -o out.png

The published figures come from tools/v1_published_runs.py; ours from one
or more tools/sweep_wave.sh tables (rows: case, excitation, variant, c,
dissipated, ...; c given as e.g. 1.5h).  One colour per nP: published as
squares, ours as a line with dots.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def published(path):
    out = {}
    with open(path) as f:
        rows = [r for r in f if not r.startswith("#")]
    for r in csv.DictReader(rows):
        out.setdefault(r["case"], []).append((float(r["c_dX"]), 100.0 * float(r["dissipated"])))
    return out


def sweep(paths):
    out = {}
    for path in paths:
        with open(path) as f:
            for line in f:
                cells = [c.strip() for c in line.strip().strip("|").split("|")]
                if len(cells) < 5 or cells[0] in ("case", "") or cells[0].startswith("-"):
                    continue
                try:
                    c = 0.0 if cells[3] == "0" else float(cells[3].rstrip("h"))
                    out.setdefault(cells[0], []).append((c, 100.0 * float(cells[4])))
                except ValueError:
                    continue
    return out


def main():
    args = sys.argv[1:]
    if "-o" not in args or len(args) < 4:
        print(__doc__)
        return 2
    k = args.index("-o")
    out = args[k + 1]
    rest = args[:k] + args[k + 2:]
    pub, ours = published(rest[0]), sweep(rest[1:])
    colours = {"1P": "tab:green", "2P": "tab:grey", "3P": "tab:blue", "4P": "tab:red"}
    fig, ax = plt.subplots(figsize=(6.4, 5.6))
    for case, col in colours.items():
        if case in pub:
            xs, ys = zip(*sorted(pub[case]))
            ax.plot(xs, ys, "s", mfc="none", color=col, ms=9, label="%s published" % case)
        if case in ours:
            xs, ys = zip(*sorted(ours[case]))
            ax.plot(xs, ys, ".-", color=col, label="%s ours (-configuration published)" % case)
    ax.set_xlabel("CG width (element sizes)")
    ax.set_ylabel("dissipated energy (%)")
    ax.set_title("V1 pulse: published runs and -configuration published")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2, loc="upper center", bbox_to_anchor=(0.5, -0.16))
    fig.tight_layout()
    fig.savefig(out, dpi=150)
    print("wrote", out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
