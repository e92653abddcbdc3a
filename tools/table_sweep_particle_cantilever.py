#!/usr/bin/python3
"""The README table of the S1 sweep (tools/sweep_particle_cantilever.sh).

usage: table_sweep_particle_cantilever.py sweep.csv [more.csv ...]

One row per stepping choice, one column per CG width; each cell is
err_avg (m) / E_max (J) / CPU s (with the largest |x1 + x2| when the
symmetry is not kept to 1 mm), or why the run did not finish.  When several
files hold the same run, the later file's row is taken.
"""
import csv
import sys

WIDTHS = ["0", "2d", "4d", "6d", "10d", "15d"]


def cell(r):
    if r is None:
        return "—"
    if r["cpu"]:
        sym = float(r["sym_dev"])
        extra = " (sym. %.2g)" % sym if sym > 1e-3 else ""
        return "%.4f / %.2f / %.0f%s" % (float(r["err_avg"]), float(r["E_max"]), float(r["cpu"]), extra)
    if "critical" in r["note"]:
        return "refused: beyond critical step"
    if " at t = " in r["note"]:
        return "stopped: 10× energy at t = %s s" % r["note"].split(" at t = ")[1].split(" s")[0]
    return r["note"][:40] or "—"


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "-help", "--help"):
        print(__doc__)
        return 0 if len(argv) >= 2 else 1
    rows = {}
    for path in argv[1:]:
        for r in csv.DictReader(open(path)):
            if r["cpu"] or (r["note"] and not r["note"].startswith("not run")):
                rows[(r["fem"], r["substeps"], r["c"])] = r
    print("| FEM, DEM steps per FEM step | " + " | ".join("c = " + w for w in WIDTHS) + " |")
    print("|---|" + "---|" * len(WIDTHS))
    for fem, name in (("newmark", "Newmark"), ("central_difference", "explicit")):
        for k in ("1", "2", "5", "20"):
            print("| %s, %s | %s |" % (name, k, " | ".join(cell(rows.get((fem, k, w))) for w in WIDTHS)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
