#!/usr/bin/python3
"""Plots of gouge_bridging runs (Voisin-Leprince et al. 2023 Figs. 4, 5, 7).

  plot_gouge_bridging.py rest OUT.png DIR[=label] ...
      Fig. 4 style: |section-averaged u_y| of the monitored plane against
      time, one curve per run folder, log scale.
  plot_gouge_bridging.py wave OUT.png DIR [t1 t2]
      Fig. 5 style: |u/I| along the bar at two times (default: when the
      incident pulse is at the left monitor and when the transmitted one is
      at the right), and the ct diagram (Fig. 7) of |u| on (y, t) beside it.
The component is the larger of u_y (P) and u_x (S); the folders are those written by gouge_bridging -output_dir.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))  # past the provenance lines
    head = [h.split(" [")[0] for h in rows[0]]
    return head, [[float(x) for x in r] for r in rows[1:] if r]


def column(path, name):
    head, rows = read_csv(path)
    k = head.index(name)
    return [r[k] for r in rows]


def rest(out, dirs):
    fig, ax = plt.subplots(figsize=(6, 4))
    for d in dirs:
        path, _, label = d.partition("=")
        t = column(path + "/history.csv", "t")
        uy = column(path + "/history.csv", "uy_0")
        ax.semilogy([1e3 * x for x in t[1:]], [max(abs(v), 1e-300) for v in uy[1:]], label=label or path)
    ax.set_xlabel("t (ms)")
    ax.set_ylabel("|mean u_y| at the monitored plane (m)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=130)


def wave(out, d, times):
    best = None
    for comp in ("ct_uy", "ct_ux"):
        head, rows = read_csv(d + "/" + comp + ".csv")
        m = max(max(abs(v) for v in r[1:]) for r in rows)
        if best is None or m > best[0]:
            best = (m, rows)
    rows = best[1]
    _, planes = read_csv(d + "/planes.csv")
    y = [p[1] for p in planes]
    t = [r[0] for r in rows]
    amp = max(max(abs(v) for v in r[1:]) for r in rows) or 1.0
    if not times:
        times = [t[len(t) // 3], t[-1]]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4))
    colours = ["tab:red", "tab:blue"]
    for tt, c in zip(times, colours):
        k = min(range(len(t)), key=lambda i: abs(t[i] - tt))
        a1.plot(y, [abs(v) / amp for v in rows[k][1:]], color=c, label="t = %.3g ms" % (1e3 * t[k]))
    a1.set_xlabel("y (m)")
    a1.set_ylabel("|u| / max |u|")
    a1.legend()
    img = [[abs(v) / amp for v in r[1:]] for r in rows]
    a2.pcolormesh(y, [1e3 * x for x in t], img, shading="nearest", cmap="viridis")
    a2.set_xlabel("y (m)")
    a2.set_ylabel("t (ms)")
    a2.set_title("ct diagram, |u| / max |u|")
    fig.tight_layout()
    fig.savefig(out, dpi=130)


def main(argv):
    if len(argv) < 4 or argv[1] not in ("rest", "wave"):
        print(__doc__)
        return 2
    if argv[1] == "rest":
        rest(argv[2], argv[3:])
    else:
        wave(argv[2], argv[3], [float(x) for x in argv[4:6]])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
