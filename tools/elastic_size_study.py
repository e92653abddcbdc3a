#!/usr/bin/python3
"""Size study of the elastic properties of periodic packings (Voisin-Leprince et al. 2023
Figs. 1a, 2a, 2b, 9a-c and Table 2): mean and standard deviation over seeds
per box size, for each probing protocol of elastic_tensor, beside the
authors' own per-seed results when their files are there.

Packings are found in the authors' layout (the stored data of GitHub
ManonVL/fem-dem-bridging-coupling, data/elastic_properties/box_*.zip unpacked):
  ROOT/box_<L>/seed_<s>/pressure_5.0/confined_5.0_MPa.data
  ROOT/box_<L>/seed_<s>/pressure_5.0/elastic_properties/properties.txt
      (K G1 G2 nu Zener E, the authors' jiggled affine probe)
or any Talus packing named on the command line with --packing L:seed:path.

  tools/elastic_size_study.py --root ROOT --out DIR [--sizes 0.006,0.009,...]
      [--seeds 1-20] [--protocols jiggled,affine,relaxed]
      [--relaxed_seeds 1-3] [--relaxed_sizes 0.006,0.009,0.018]
      [--exe build/bin/elastic_tensor] [--plot_only]
DIR/runs.csv gains one row per packing and protocol as each run ends (with
its wall time); rows already there are kept and not run again, so a study
can be stopped and continued, or extended by another protocol or size.
Writes
DIR/table.md (mean ± sd per size and protocol) and DIR/size_study.png.
Protocols: jiggled = -probe affine -probe_jiggle 1e-5 (the scripts'),
affine = -probe affine -probe_jiggle 0, relaxed = -probe relaxed
-probe_jiggle 0, authors = their properties.txt.
"""
import argparse
import csv
import glob
import math
import os
import re
import subprocess
import sys
import tempfile
import time

KEYS = ["E", "nu", "K", "G1", "G2", "zener", "density_packing", "pressure", "packing_fraction"]
PROTOCOL_ARGS = {
    "jiggled": ["-probe", "affine", "-probe_jiggle", "1e-5"],
    "affine": ["-probe", "affine", "-probe_jiggle", "0"],
    "relaxed": ["-probe", "relaxed", "-probe_jiggle", "0"],
}


def parse_range(text):
    out = []
    for part in text.split(","):
        if "-" in part:
            a, b = part.split("-")
            out += list(range(int(a), int(b) + 1))
        elif part:
            out.append(int(part))
    return out


def box_dirs(root):
    """{L (m): dir} for the authors' box_<L> folders (their names carry
    floating-point noise: box_0.009000000000000001)."""
    out = {}
    for d in glob.glob(os.path.join(root, "box_*")):
        if os.path.isdir(d):
            out[round(float(os.path.basename(d)[4:]), 6)] = d
    return out


def run_one(exe, path, protocol, extra):
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.time()
        res = subprocess.run([exe, "-input", path, "-scratch", os.path.join(tmp, "ref.h5")] +
                             PROTOCOL_ARGS[protocol] + extra, capture_output=True, text=True)
        wall = time.time() - t0
    if res.returncode != 0:
        sys.exit(f"elastic_tensor failed on {path} ({protocol}):\n{res.stdout[-1500:]}{res.stderr[-1500:]}")
    line = [l for l in res.stdout.splitlines() if l.startswith("summary:")][-1]
    vals = dict(kv.split("=", 1) for kv in line[len("summary:"):].split())
    row = {k: float(vals[k]) for k in KEYS}
    row["wall"] = wall
    row["relax_steps"] = float(vals.get("relax_steps", 0))
    return row


def authors_row(seed_dir):
    p = os.path.join(seed_dir, "pressure_5.0", "elastic_properties", "properties.txt")
    if not os.path.exists(p):
        return None
    with open(p) as f:
        v = [float(x) for x in [l for l in f if not l.startswith("#")][0].split()]
    K, G1, G2, nu, Z, E = v
    return {"E": E, "nu": nu, "K": K, "G1": G1, "G2": G2, "zener": Z}


def stats(values):
    v = [x for x in values if x == x]
    if not v:
        return float("nan"), float("nan")
    m = sum(v) / len(v)
    sd = math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1)) if len(v) > 1 else 0.0
    return m, sd


def write_table(rows, path):
    groups = {}
    for r in rows:
        groups.setdefault((r["protocol"], float(r["L"])), []).append(r)
    order = ["authors", "jiggled", "affine", "relaxed"]
    lines = ["| protocol | L/d0 | seeds | E (GPa) | nu | K (GPa) | G1 = C44 (GPa) | G2 (GPa) | Zener | "
             "density (kg/m3) | p (MPa) | wall per run (s) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for proto in order:
        for L in sorted({k[1] for k in groups if k[0] == proto}):
            g = groups[(proto, L)]
            cell = []
            for k, scale, fmt in [("E", 1e-9, "%.4f"), ("nu", 1, "%.4f"), ("K", 1e-9, "%.4f"), ("G1", 1e-9, "%.4f"),
                                  ("G2", 1e-9, "%.4f"), ("zener", 1, "%.3f"), ("density_packing", 1, "%.1f"),
                                  ("pressure", 1e-6, "%.3f")]:
                m, sd = stats([float(r[k]) * scale for r in g if r.get(k, "") not in ("", None)])
                cell.append("–" if m != m else (fmt % m) + " ± " + (fmt % sd))
            w, _ = stats([float(r["wall"]) for r in g if r.get("wall", "") not in ("", None)])
            lines.append(f"| {proto} | {L / 0.003:.0f} | {len(g)} | " + " | ".join(cell) +
                         f" | {'–' if w != w else '%.2f' % w} |")
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(path + ".tmp", path)
    print("\n".join(lines))


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    panels = [("zener", 1, "Zener index 2C44/(C11-C12) (Fig. 1a)"), ("E", 1e-9, "Young's modulus E (GPa) (Fig. 2a)"),
              ("nu", 1, "Poisson's ratio (Fig. 2b)"), ("G1", 1e-9, "G1 = C44 (GPa) (Fig. 9a)"),
              ("G2", 1e-9, "G2 = (C11-C12)/2 (GPa) (Fig. 9a)"), ("K", 1e-9, "bulk modulus K (GPa) (Fig. 9b)")]
    style = {"authors": ("k", "o"), "jiggled": ("tab:blue", "s"), "affine": ("tab:green", "^"),
             "relaxed": ("tab:red", "v")}
    fig, axes = plt.subplots(2, 3, figsize=(14, 8))
    for ax, (key, scale, title) in zip(axes.flat, panels):
        for k, proto in enumerate(["authors", "jiggled", "affine", "relaxed"]):
            sizes = sorted({float(r["L"]) for r in rows if r["protocol"] == proto})
            if not sizes:
                continue
            xs, ms, sds = [], [], []
            for L in sizes:
                m, sd = stats([float(r[key]) * scale for r in rows if r["protocol"] == proto and float(r["L"]) == L
                               and r.get(key, "") not in ("", None)])
                xs.append(L / 0.003 + 0.15 * (k - 1.5))
                ms.append(m)
                sds.append(sd)
            c, mk = style[proto]
            ax.errorbar(xs, ms, yerr=sds, color=c, marker=mk, capsize=3, label=proto, linestyle="-")
        if key == "E":
            ax.axhline(0.977, color="gray", linestyle=":", label="Table 2")
        if key == "nu":
            ax.axhline(0.255, color="gray", linestyle=":", label="Table 2")
        if key == "zener":
            ax.axhline(1.0, color="gray", linestyle=":")
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("L / d0")
        ax.grid(alpha=0.3)
    axes.flat[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path + ".tmp.png", dpi=110)
    os.replace(path + ".tmp.png", path)
    print(f"wrote {path}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--root", default="")
    ap.add_argument("--out", required=True)
    ap.add_argument("--sizes", default="")
    ap.add_argument("--seeds", default="1-20")
    ap.add_argument("--protocols", default="jiggled,affine")
    ap.add_argument("--relaxed_seeds", default="1-3")
    ap.add_argument("--relaxed_sizes", default="")
    ap.add_argument("--exe", default="build/bin/elastic_tensor")
    ap.add_argument("--extra", default="", help="further elastic_tensor options, space separated")
    ap.add_argument("--packing", action="append", default=[], help="L:seed:path of a Talus packing")
    ap.add_argument("--plot_only", action="store_true")
    ap.add_argument("--check_table2", action="store_true",
                    help="exit 1 unless the jiggled probe at 12 d0 gives Table 2 (E 0.977 GPa within 1 %%, "
                         "nu 0.255 within 0.005); exit 77 (skip) when --root does not exist")
    a = ap.parse_args()
    if a.check_table2 and not os.path.isdir(a.root):
        print(f"SKIPPED: no packings at --root '{a.root}' (unpack the authors' data/elastic_properties/box_*.zip "
              "there and set TALUS_ELASTIC_AUTHORS_DIR)")
        sys.exit(77)
    os.makedirs(a.out, exist_ok=True)
    runs = os.path.join(a.out, "runs.csv")
    fields = ["protocol", "L", "seed", "path"] + KEYS + ["wall", "relax_steps"]
    if not a.plot_only:
        protos = [p for p in a.protocols.split(",") if p]
        for p in protos:
            if p not in PROTOCOL_ARGS:
                sys.exit(f"--protocols: unknown protocol {p} (jiggled, affine, relaxed)")
        seeds = parse_range(a.seeds)
        rseeds = parse_range(a.relaxed_seeds)
        boxes = box_dirs(a.root) if a.root else {}
        sizes = [round(float(x), 6) for x in a.sizes.split(",") if x] or sorted(boxes)
        rsizes = [round(float(x), 6) for x in a.relaxed_sizes.split(",") if x] or None  # None: every size
        jobs = []
        for L in sizes:
            if L not in boxes:
                sys.exit(f"--sizes: no box_{L} under {a.root} (have {sorted(boxes)})")
            for s in seeds:
                sd = os.path.join(boxes[L], f"seed_{s}")
                data = os.path.join(sd, "pressure_5.0", "confined_5.0_MPa.data")
                if not os.path.exists(data):
                    continue
                jobs.append((L, s, data, sd))
        for spec in a.packing:
            L, s, path = spec.split(":", 2)
            jobs.append((float(L), int(s), path, None))
        done = set()
        if os.path.exists(runs):
            with open(runs, newline="") as f:
                for r in csv.DictReader(f):
                    done.add((r["protocol"], round(float(r["L"]), 6), int(r["seed"])))
        else:
            with open(runs, "w", newline="") as f:
                csv.DictWriter(f, fieldnames=fields).writeheader()

        def append(row):
            with open(runs, "a", newline="") as f:
                csv.DictWriter(f, fieldnames=fields, extrasaction="ignore").writerow(row)
                f.flush()
                os.fsync(f.fileno())

        extra = a.extra.split()
        for L, s, data, sd in jobs:
            if sd and ("authors", round(L, 6), s) not in done:
                ar = authors_row(sd)
                if ar:
                    append(dict(protocol="authors", L=L, seed=s, path=data, **ar))
            for p in protos:
                if p == "relaxed" and (s not in rseeds or (rsizes is not None and round(L, 6) not in rsizes)):
                    continue
                if (p, round(L, 6), s) in done:
                    continue
                r = run_one(a.exe, data, p, extra)
                append(dict(protocol=p, L=L, seed=s, path=data, **r))
                print(f"L={L / 0.003:.0f}d0 seed {s} {p}: E={r['E']:.5g} nu={r['nu']:.4f} Z={r['zener']:.4f} "
                      f"wall {r['wall']:.2f} s", flush=True)
    with open(runs, newline="") as f:
        rows = list(csv.DictReader(f))
    write_table(rows, os.path.join(a.out, "table.md"))
    try:
        plot(rows, os.path.join(a.out, "size_study.png"))
    except ImportError:
        print("matplotlib not found: no plot (table.md and runs.csv written)")
    if a.check_table2:
        g = [r for r in rows if r["protocol"] == "jiggled" and abs(float(r["L"]) - 0.036) < 1e-9]
        E, _ = stats([float(r["E"]) for r in g])
        nu, _ = stats([float(r["nu"]) for r in g])
        ok = len(g) >= 3 and abs(E - 0.977e9) <= 0.01 * 0.977e9 and abs(nu - 0.255) <= 0.005
        print(f"Table 2 check: jiggled probe at 12 d0 over {len(g)} seeds: E = {E:.6g} Pa (0.977e9 within 1 %), "
              f"nu = {nu:.5f} (0.255 within 0.005): {'ok' if ok else 'FAILED'}")
        sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
