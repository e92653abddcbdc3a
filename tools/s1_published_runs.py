#!/usr/bin/python3
"""S1 figures of the paper's own runs, measured as particle_cantilever measures ours.

usage: s1_published_runs.py <checkout of github.com/chyalexcheng/Oomph-Mercury> [out.csv]

The authors published their S1 output (folder SingleSphere/, one sub-folder
per CG width: Default = c 0, CGnR = c n particle radii).  For each width this
reads the MercuryDPM particle file (.data), the MercuryDPM energies (.ene)
and the oomph-lib beam trace (Trace.dat) and prints, in the definitions of
Drivers/particle_cantilever.c:
  err_avg  time average until t_off of sqrt(mean over the two particles of
           (x - x0)^2 + (z - z_ref(y))^2), z_ref the quasi-static point-load path;
  sym_dev  largest |x1 + x2| while on the beam;
  lat_dev  largest |x - x0| while on the beam;
  E_max    largest total energy while on the beam: particles' kinetic +
           contact elastic + gravitational (relative to the start) + beam
           kinetic + strain (the sum the authors plot in their Fig. 17);
  t_off    first output time with both particles beyond y = L.
Their frame is shifted (beam y in [-6, 6] m, clamped at -6) and in mm, ms,
ug: converted here.  The beam trace is sampled with the particle files
(row k with row k, as the authors' own plotting script pairs them).
"""
import math
import os
import sys

CASES = [("Default", "0"), ("CG4R", "2d"), ("CG8R", "4d"), ("CG12R", "6d"), ("CG20R", "10d")]
RHO_G, D, G, E, B, L, X0 = 2e4, 0.2, 9.81, 1e8, 0.8, 12.0, 0.2
MASS = RHO_G * math.pi / 6.0 * D ** 3
I = B ** 4 / 12.0
F = 2.0 * MASS * G
J_SCALE = 1e-9  # their energy unit (ug mm^2 / ms^2) in J


def read_particles(path):
    """Times (s) and the two particles' positions (m, clamp at y = 0)."""
    t, p1, p2 = [], [], []
    with open(path) as f:
        lines = f.read().split("\n")
    for i in range(0, len(lines) - 2, 3):
        head = lines[i].split()
        if len(head) < 2:
            break
        t.append(float(head[1]) * 1e-3)
        for p, line in ((p1, lines[i + 1]), (p2, lines[i + 2])):
            x, y, z = (float(v) * 1e-3 for v in line.split()[:3])
            p.append((x, y + L / 2.0, z))
    return t, p1, p2


def read_table(path, skip):
    rows = []
    with open(path) as f:
        for k, line in enumerate(f):
            if k < skip or not line.strip():
                continue
            rows.append([float(v) for v in line.split()])
    return rows


def measure(folder):
    t, p1, p2 = read_particles(os.path.join(folder, "SingleSphere.data"))
    z0 = p1[0][2]

    def z_ref(y):
        y = min(max(y, 0.0), L)
        return z0 - F * y ** 3 / (3.0 * E * I)

    n_on = len(t)
    for k in range(len(t)):
        if p1[k][1] > L and p2[k][1] > L:
            n_on = k
            break
    t_off = t[n_on] if n_on < len(t) else float("nan")
    err = []
    for k in range(n_on):
        e2 = 0.0
        for p, x0 in ((p1[k], X0), (p2[k], -X0)):
            e2 += 0.5 * ((p[0] - x0) ** 2 + (p[2] - z_ref(p[1])) ** 2)
        err.append(math.sqrt(e2))
    area = sum(0.5 * (err[k] + err[k + 1]) * (t[k + 1] - t[k]) for k in range(n_on - 1))
    err_avg = area / (t[n_on - 1] - t[0])
    sym = max(abs(p1[k][0] + p2[k][0]) for k in range(n_on))
    lat = max(max(abs(p1[k][0] - X0), abs(p2[k][0] + X0)) for k in range(n_on))
    ene = read_table(os.path.join(folder, "SingleSphere.ene"), 1)
    trace = read_table(os.path.join(folder, "Trace.dat"), 0)
    n = min(len(ene), len(trace))
    # .ene: time mass momentum(3) angMomentum(3) gravitEnergy traKinetic rotKinetic elastic ...
    # Trace.dat: ... kinetic (column 12) and strain (column 13) energy of the beam.
    e_max = -math.inf
    e0 = None
    for k in range(n):
        if ene[k][0] * 1e-3 > t_off:
            break
        e_dem = ene[k][8] - ene[0][8] + ene[k][9] + ene[k][10] + ene[k][11]
        e_tot = (e_dem + trace[k][12] + trace[k][13]) * J_SCALE
        e0 = e_tot if e0 is None else e0
        e_max = max(e_max, e_tot)
    return dict(err_avg=err_avg, sym_dev=sym, lat_dev=lat, E_max=e_max, E0=e0, t_off=t_off)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    root = os.path.join(sys.argv[1], "SingleSphere")
    if not os.path.isdir(root):
        sys.exit(f"s1_published_runs: no folder SingleSphere in {sys.argv[1]} (a checkout of chyalexcheng/Oomph-Mercury)")
    rows = []
    print(f"{'c':>4} {'err_avg (m)':>12} {'sym_dev (m)':>12} {'lat_dev (m)':>12} {'E_max (J)':>10} {'E_start (J)':>11} {'t_off (s)':>9}")
    for sub, c in CASES:
        r = measure(os.path.join(root, sub))
        rows.append((c, r))
        print(f"{c:>4} {r['err_avg']:12.4f} {r['sym_dev']:12.3g} {r['lat_dev']:12.3g} {r['E_max']:10.2f} {r['E0']:11.3f} {r['t_off']:9.2f}")
    if len(sys.argv) > 2:
        tmp = sys.argv[2] + ".tmp"
        with open(tmp, "w") as f:
            f.write("c,err_avg,sym_dev,lat_dev,E_max,E_start,t_off\n")
            for c, r in rows:
                f.write(f"{c},{r['err_avg']:.6g},{r['sym_dev']:.6g},{r['lat_dev']:.6g},{r['E_max']:.6g},{r['E0']:.6g},{r['t_off']:.6g}\n")
        os.replace(tmp, sys.argv[2])


if __name__ == "__main__":
    main()
