#!/usr/bin/python3
"""Plots a hopper_discharge run: discharged mass against time for each
orifice, and the flow rate against the orifice diameter with the Beverloo
fit W = C rho_b sqrt(g) (D - k d)^(5/2).

    python3 plot_hopper.py <output_dir> [out.png]
"""
import csv
import glob
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def read_rates(path):
    rows, meta, fit = [], {}, {}
    with open(path) as f:
        for line in f:
            if line.startswith("# fit:"):
                m = re.match(r"# fit: C (\S+) k (\S+); C with k = 1.5: (\S+)", line)
                if m:
                    fit = {"C": float(m.group(1)), "k": float(m.group(2)), "C15": float(m.group(3))}
            elif line.startswith("#"):
                for key in ("d_mean", "rho_b", "g"):
                    m = re.search(key + r" ([-+0-9.eE]+)", line)
                    if m:
                        meta[key] = float(m.group(1))
            elif line.strip():
                D, Dd, W, clog, window = line.strip().split(",")
                rows.append((float(D), float(Dd), float(W), int(clog)))
    return rows, meta, fit


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else "results/hopper_discharge"
    png = sys.argv[2] if len(sys.argv) > 2 else os.path.join(out_dir, "hopper_discharge.png")
    rows, meta, fit = read_rates(os.path.join(out_dir, "rates.csv"))
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2))
    for i, (D, Dd, W, clog) in enumerate(rows):
        path = os.path.join(out_dir, "discharge_%d.csv" % i)
        t, m = [], []
        with open(path) as f:
            for r in csv.reader(line for line in f if not line.startswith("#")):
                try:
                    t.append(float(r[0]))
                    m.append(float(r[1]))
                except (ValueError, IndexError):
                    pass
        a.plot(t, [1e3 * x for x in m], label="D = %.3g d" % Dd)
    a.set_xlabel("time after opening [s]")
    a.set_ylabel("discharged mass [g]")
    a.legend()
    a.set_title("discharge")
    Ds = [r[0] for r in rows]
    Ws = [r[2] for r in rows]
    b.plot([1e3 * D for D in Ds], [1e3 * W for W in Ws], "o", label="measured")
    d, rho, g = meta.get("d_mean"), meta.get("rho_b"), meta.get("g", 9.81)
    if d and rho and fit and math.isfinite(fit.get("C", float("nan"))):
        lo, hi = min(Ds) * 0.9, max(Ds) * 1.1
        xs = [lo + (hi - lo) * k / 100 for k in range(101)]
        C, k = fit["C"], fit["k"]
        b.plot([1e3 * x for x in xs], [1e3 * C * rho * math.sqrt(g) * max(x - k * d, 0) ** 2.5 for x in xs],
               "-", label="Beverloo fit C = %.3f, k = %.2f" % (C, k))
        if math.isfinite(fit.get("C15", float("nan"))):
            C15 = fit["C15"]
            b.plot([1e3 * x for x in xs], [1e3 * C15 * rho * math.sqrt(g) * max(x - 1.5 * d, 0) ** 2.5 for x in xs],
                   "--", label="k = 1.5: C = %.3f" % C15)
    b.set_xlabel("orifice diameter D [mm]")
    b.set_ylabel("flow rate W [g/s]")
    b.legend()
    b.set_title("rate against Beverloo")
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    print("wrote", png)


if __name__ == "__main__":
    main()
