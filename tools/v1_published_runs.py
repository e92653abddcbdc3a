#!/usr/bin/python3
"""V1 figures of the paper's own runs, measured as wave_volume_coupling measures ours.

usage: v1_published_runs.py <Oomph-Mercury checkout or its git directory> [out.csv] [FOLDER=OURDIR ...]

The authors published their V1 pulse runs (folder PulseWave/oneDimChain{1,8,27,64}P,
one sub-folder per CG width: Default = c 0, CGnR = c n particle radii; ref/ the
full-DEM bar, 1P only).  For each run this reads the MercuryDPM energies
(.ene: weighted particle mass, momentum, kinetic and elastic energy), the
oomph-lib trace (Trace.dat: the solid's weighted mass, momentum, kinetic and
strain energy, paired row k with row k as the authors' own plotting script
does), the particle file (.data, where stored: 1P) and the restart file's
parameters, and prints, in the definitions of Drivers/wave_volume_coupling.c:
  dissipated       1 - E_coupled(t_end) / E_reference(t_end), t_end = 0.09 s (the
                   last output at or before it); E_reference from ref/ (1P) or the
                   coupled run's own E(0) (the full DEM keeps it to 3e-4)
  dissipated_fig   the authors' figure: 1 - E(row last) / E(row 20), rows of 0.964 ms:
                   last = 63 for 1P (t = 19.3 and 60.8 ms; their plotDissipation's default
                   window), 82 for 2P-4P (79.1 ms; their call for 8P-64P passes lastIter=83)
  t_last_s         time of the last stored row (3P c = 0 stops at 53 ms: its dissipated is
                   taken there, after the wave has left the overlap)
  trace_offset     the shift k of Trace.dat rows against .ene rows (trace row j + k with
                   ene row j) that keeps the total momentum closest to its initial value
                   over rows 25-59 (before the far end reflects): 0, the rows pair one to one
  cell_m           the restart file's search-cell size (hGrid cellSizes): the particle
                   diameter, the grid Eq. 18's particles are gathered on
  momentum_drift   largest |P_coupled - P_reference| / max |P_reference| before
                   t = 0.9 L / sqrt(E / rho) (P_reference: ref/, or the initial P)
  mass_err0, mass_err  |m_DE + m_FE - rho V| / rho V at t = 0, largest over the run
  profile_err      relative L2 difference of the particles' v_y layer profile
                   (y <= 12 m, our frame) from ref/ at 0.03 and 0.05 s (1P only: the
                   .data files of 8P-64P are not stored)
and the parameters (particles, radius, stiffness, density, dt / t_c, t_max) against
the driver's defaults.  Their frame is mirrored and shifted (pulse at y = 13.8 m
moving -y; ours at y = 0.2 m) and in mm, ms, ug: converted here.  The penalty,
the weights and the CG width are not stored in the files: the width is read
from the folder name, the weights from the weighted masses.

FOLDER=OURDIR (1P only, e.g. Default=results/pub_c0): compares the v_y layer
profile (y <= 12 m) of our run in OURDIR (its profiles.csv, run with
-profile_times at the published frames 0.0308628064,0.0501520604) with the
published coupled run in FOLDER, and our full-DEM reference with theirs.
"""
import math
import os
import subprocess
import sys

E_MOD, RHO, DX, LENGTH, WIDTH, T_END = 1e8, 1309.0, 0.4, 20.0, 0.8, 0.09
J = 1e-9      # ug mm^2 / ms^2 -> J;  ug mm / ms -> kg m / s;  ug -> kg
CASES = {1: ["Default", "CG1R", "CG2R", "CG3R", "CG4R", "CG5R"],
         8: ["Default", "CG2R", "CG4R", "CG6R", "CG8R", "CG10R"],
         27: ["Default", "CG3R", "CG6R", "CG9R", "CG12R", "CG15R"],
         64: ["Default", "CG4R", "CG8R", "CG12R", "CG16R", "CG20R"]}


class Source:
    """A checkout (folders) or a git directory (read with git show)."""

    def __init__(self, path):
        self.path = path
        self.git = os.path.isdir(os.path.join(path, "objects"))

    def read(self, rel):
        if self.git:
            r = subprocess.run(["git", "--git-dir", self.path, "show", "HEAD:" + rel], capture_output=True)
            if r.returncode != 0:
                return None
            return r.stdout.decode()
        p = os.path.join(self.path, rel)
        if not os.path.exists(p):
            return None
        with open(p) as f:
            return f.read()


def table(text, skip=0):
    rows = []
    for k, line in enumerate(text.split("\n")):
        if k < skip or not line.strip():
            continue
        rows.append([float(v) for v in line.split()])
    return rows


def frames(text):
    """(time s, [(y_ours m, vy_ours m/s), ...]) per output of a .data file."""
    lines, out, i = text.split("\n"), [], 0
    while i < len(lines) and lines[i].strip():
        head = lines[i].split()
        n, t = int(head[0]), float(head[1]) * 1e-3
        ps = []
        for k in range(n):
            v = lines[i + 1 + k].split()
            ps.append((14.0 - float(v[1]) * 1e-3, -float(v[4])))
        out.append((t, ps))
        i += n + 1
    return out


def layer_profile(ps):
    acc = {}
    for y, vy in ps:
        key = round(y / 1e-3)
        s, c = acc.get(key, (0.0, 0))
        acc[key] = (s + vy, c + 1)
    return {k: s / c for k, (s, c) in acc.items()}


def restart_params(text):
    p = {}
    for line in text.split("\n"):
        w = line.split()
        if not w:
            continue
        if w[0] == "timeStep":
            p["dt"] = float(w[1]) * 1e-3
            p["t_max"] = float(w[w.index("timeMax") + 1]) * 1e-3
        elif w[0].endswith("Species") and "density" in w:
            p["density"] = float(w[w.index("density") + 1])
            p["stiffness"] = float(w[w.index("stiffness") + 1]) * 1e-3      # ug/ms^2 -> N/m
            p["dissipation"] = float(w[w.index("dissipation") + 1])
            if "adhesionForceMax" in w:
                p["adhesion_force_max"] = float(w[w.index("adhesionForceMax") + 1])
        elif w[0] == "hGrid" and "cellSizes" in w:
            p["cell"] = float(w[w.index("cellSizes") + 1]) * 1e-3
        elif w[0] == "Particles":
            p["particles"] = int(w[1])
        elif w[0] == "BaseParticle" and "radius" not in p:
            p["radius"] = float(w[w.index("radius") + 1]) * 1e-3
    return p


def compare_profiles(src, folder, ours_dir, ref_data, out):
    """Our particles' layer profile against the published coupled run, and our reference against theirs."""
    import csv
    pub = frames(src.read("PulseWave/oneDimChain1P/%s/oneDimChain.data" % folder))
    with open(os.path.join(ours_dir, "profiles.csv")) as f:
        rows = list(csv.DictReader(f))
    times = sorted(set(float(r["t"]) for r in rows))
    num = den = num_r = den_r = 0.0
    for ts in times:
        kp = min(range(len(pub)), key=lambda i: abs(pub[i][0] - ts))
        a, b = layer_profile(pub[kp][1]), layer_profile(ref_data[kp][1])
        for r in rows:
            if float(r["t"]) != ts or float(r["y"]) > 12.0:
                continue
            key = round(float(r["y"]) / 1e-3)
            if key in a and key in b:
                num += (float(r["vy"]) - a[key]) ** 2
                den += a[key] ** 2
                num_r += (float(r["vy_ref"]) - b[key]) ** 2
                den_r += b[key] ** 2
    print("# 1P %s against %s (t = %s s): particle profile error against the published coupled run %.4f, "
          "our full-DEM reference against theirs %.2e" % (folder, ours_dir, ", ".join("%.6g" % t for t in times),
                                                         math.sqrt(num / den), math.sqrt(num_r / den_r)), file=out)


def energy(ene, trace, k):
    e, t = ene[k], trace[k]
    return (e[9] + e[10] + e[11] + t[11] + t[13]) * J


def main():
    if len(sys.argv) < 2:
        print(__doc__)
        return 2
    src = Source(sys.argv[1])
    out = open(sys.argv[2], "w") if len(sys.argv) > 2 else sys.stdout
    ref_ene = table(src.read("PulseWave/oneDimChain1P/ref/OneDimChainMercury.ene"), 1)
    ref_data = frames(src.read("PulseWave/oneDimChain1P/ref/OneDimChainMercury.data"))
    ref_par = restart_params(src.read("PulseWave/oneDimChain1P/ref/OneDimChainMercury.restart"))
    mexact = RHO * LENGTH * WIDTH * WIDTH
    t_refl = 0.9 * LENGTH / math.sqrt(E_MOD / RHO)
    cols = ["case", "folder", "c_dX", "dissipated", "dissipated_fig", "momentum_drift", "mass_err0", "mass_err",
            "profile_err", "t_last_s", "trace_offset", "cell_m", "E0_J", "particles", "radius_m", "stiffness_N_m", "density_kg_m3", "dt_over_tc",
            "t_max_s", "contact_tension", "mass_dem_kg", "mass_fem_kg"]
    print(",".join(cols), file=out)
    checks = []
    for nP, folders in CASES.items():
        n = round(nP ** (1.0 / 3.0))
        d = DX / n
        m = 6.0 * RHO / math.pi * math.pi * d ** 3 / 6.0
        k = E_MOD * d
        tc = math.pi * math.sqrt(0.5 * m / k)
        for folder in folders:
            base = "PulseWave/oneDimChain%dP/%s/" % (nP, folder)
            ene_t, trace_t = src.read(base + "oneDimChain.ene"), src.read(base + "Trace.dat")
            if ene_t is None or trace_t is None:
                continue
            ene, trace = table(ene_t, 1), table(trace_t)
            rows = min(len(ene), len(trace))
            par = restart_params(src.read(base + "oneDimChain.restart") or "")
            c_r = 0.0 if folder == "Default" else float(folder[2:-1])
            c_dx = c_r * par["radius"] / DX
            times = [ene[r][0] * 1e-3 for r in range(rows)]
            last = max(r for r in range(rows) if times[r] <= T_END + 1e-9)
            E = [energy(ene, trace, r) for r in range(rows)]
            with_ref = nP == 1
            E_ref = sum(ref_ene[last][c] for c in (9, 10, 11)) * J if with_ref else E[0]
            dissipated = 1.0 - E[last] / E_ref
            fig_row = 63 if nP == 1 else 82
            fig = 1.0 - E[fig_row] / E[20] if rows > fig_row else float("nan")
            def momentum_spread(k):
                return max(abs((ene[r][3] + trace[r + k][6]) - (ene[0][3] + trace[k][6])) * J
                           for r in range(25, min(60, rows - 1)) if 0 <= r + k < len(trace))
            offset = min((-1, 0, 1), key=momentum_spread)
            P = [(ene[r][3] + trace[r][6]) * J for r in range(rows)]
            P_ref = [ref_ene[r][3] * J for r in range(len(ref_ene))] if with_ref else [P[0]] * rows
            pmax = max(abs(v) for v in P_ref)
            drift = max(abs(P[r] - P_ref[r]) / pmax for r in range(min(rows, len(P_ref))) if times[r] < t_refl)
            masses = [(ene[r][1] + trace[r][4]) * J for r in range(rows)]
            mass_err0 = abs(masses[0] - mexact) / mexact
            mass_err = max(abs(v - mexact) / mexact for v in masses[: last + 1])
            perr = float("nan")
            data_t = src.read(base + "oneDimChain.data") if with_ref else None
            if data_t:
                cf = frames(data_t)
                num = den = 0.0
                for ts in (0.03, 0.05):
                    kc = min(i for i, f in enumerate(cf) if f[0] >= ts - 1e-9)
                    kr = min(i for i, f in enumerate(ref_data) if f[0] >= ts - 1e-9)
                    a, b = layer_profile(cf[kc][1]), layer_profile(ref_data[kr][1])
                    for key, va in a.items():
                        if key * 1e-3 <= 12.0 and key in b:
                            num += (va - b[key]) ** 2
                            den += b[key] ** 2
                perr = math.sqrt(num / den) if den > 0 else float("nan")
            tension = "no" if par.get("adhesion_force_max", 1.0) == 0.0 else "yes"
            print(",".join(str(v) for v in [
                "%dP" % n, folder, "%.2f" % c_dx, "%.4f" % dissipated, "%.4f" % fig, "%.3g" % drift,
                "%.3g" % mass_err0, "%.3g" % mass_err, "%.4f" % perr, "%.4g" % times[last], offset,
                "%.4g" % par.get("cell", float("nan")), "%.4f" % E[0], par.get("particles"),
                "%.4g" % par.get("radius"), "%.4g" % par.get("stiffness"), "%.4g" % par.get("density"),
                "%.4g" % (par["dt"] / tc), "%.4g" % par["t_max"], tension, "%.1f" % (ene[0][1] * J),
                "%.1f" % (trace[0][4] * J)]), file=out)
            # the driver's defaults against the restart file
            want = {"particles": round(WIDTH / d) ** 2 * round(12.0 / d), "radius": d / 2, "stiffness": k,
                    "density": 6 * RHO / math.pi, "dt": 0.01 * tc, "cell": d}
            for key, v in want.items():
                got = par.get(key)
                if got is None or abs(got - v) > 1e-5 * abs(v):  # rho = 1309 rounds rho_g to 2500
                    checks.append("%dP %s: %s = %s in the restart file, the driver's default %s" % (n, folder, key, got, v))
    print("# full-DEM reference (1P): %d particles, dt / t_c = %.4g, tension %s" % (
        ref_par["particles"], ref_par["dt"] / (math.pi * math.sqrt(0.5 * (6 * RHO / math.pi) * math.pi * DX ** 3 / 6
                                                                     / (E_MOD * DX))),
        "no" if ref_par.get("adhesion_force_max", 1.0) == 0.0 else "yes"), file=out)
    for c in checks:
        print("# differs: " + c, file=out)
    for arg in sys.argv[3:]:
        folder, ours = arg.split("=", 1)
        compare_profiles(src, folder, ours, ref_data, out)
    if not checks:
        print("# every run's particle count, radius, stiffness, density and dt equal the driver's defaults to 1e-5,"
              " its search cells are one particle diameter"
              " (their rho_g = 2500 against 6 x 1309 / pi = 2500.006)", file=out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
