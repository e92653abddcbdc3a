#!/usr/bin/python3
"""Side-by-side affine strain probe of one packing by LAMMPS and by Talus.

LAMMPS reads the data file, evaluates the stress at once (run 0, the
gouge law pair_style gran/hertz/history 3.663e10 4.5249e10 0.2 NULL 0.5 1,
as the Voisin-Leprince et al.'s contact_law.mod) for the reference and for +-eps on
each of the six Voigt components (change_box ... remap, the LAMMPS ELASTIC
example's maps), every probe from a fresh read of the file; the tensor is
C_iJ = (sigma_i(+eps_J) - sigma_i(-eps_J)) / (2 eps), sigma = -p.  Talus's
elastic_tensor probes the same file with -probe affine -probe_jiggle 0.
Prints both symmetrised tensors, the largest difference relative to the
largest entry and the moduli of both.

  tools/elastic_lammps_probe.py DATA [--talus build/bin/elastic_tensor]
                                [--lmp lmp] [--strain 1e-6]
Last line: summary: n=... max_rel=... E_talus=... E_lammps=...
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

VOIGT = ["xx", "yy", "zz", "yz", "xz", "xy"]
# LAMMPS pressure components in Voigt order
PCOMP = ["pxx", "pyy", "pzz", "pyz", "pxz", "pxy"]


def change_box(J, delta_sign, up):
    """change_box command of probe J with strain delta_sign * up (the box is
    read orthogonal then made triclinic, so the tilts start at zero)."""
    e = delta_sign * up
    if J == 0:
        return f"change_box all x delta 0 $(v_e*lx) xy delta $(v_e*xy) xz delta $(v_e*xz) remap units box", e
    if J == 1:
        return f"change_box all y delta 0 $(v_e*ly) yz delta $(v_e*yz) remap units box", e
    if J == 2:
        return f"change_box all z delta 0 $(v_e*lz) remap units box", e
    if J == 3:
        return f"change_box all yz delta $(v_e*lz) remap units box", e
    if J == 4:
        return f"change_box all xz delta $(v_e*lz) remap units box", e
    return f"change_box all xy delta $(v_e*ly) remap units box", e


def lammps_input(data, up, restart):
    if restart:
        # a LAMMPS restart keeps the box (triclinic), the atoms and the
        # pair style's contact histories; the style itself is given again
        read = f"""clear
box tilt large
read_restart {data}
"""
    else:
        read = f"""clear
units si
boundary p p p
atom_style sphere
atom_modify map array
box tilt large
read_data {data}
change_box all triclinic
"""
    setup = read + f"""pair_style gran/hertz/history 36630036630.03663 45248868778.28054 0.2 NULL 0.5 1
pair_coeff * *
comm_modify vel yes
neighbor 0.001 bin
neigh_modify check yes
timestep 1e-08
fix integr all nve/sphere
thermo_style custom step pxx pyy pzz pyz pxz pxy
"""
    if restart:
        setup += "run 0\n"  # change_box refuses to run before the restart's per-atom data are in place
    out = []
    out.append(setup + "run 0\n" + 'print "PROBE ref 0 ' + " ".join(f"$({c}:%.17g)" for c in PCOMP) + '"\n')
    for J in range(6):
        for sgn in (-1, 1):
            cmd, e = change_box(J, sgn, up)
            out.append(setup + f"variable e equal {e:.17g}\n" + cmd + "\nrun 0\n" +
                       f'print "PROBE {J} {sgn} ' + " ".join(f"$({c}:%.17g)" for c in PCOMP) + '"\n')
    return "".join(out)


def run_lammps(lmp, data, up, restart=False):
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "probe.in")
        with open(path, "w") as f:
            f.write(lammps_input(os.path.abspath(data), up, restart))
        res = subprocess.run([lmp, "-in", path, "-log", "none"], capture_output=True, text=True, cwd=tmp)
    if res.returncode != 0:
        sys.exit(f"lammps failed: {res.stderr[-2000:]}{res.stdout[-2000:]}")
    sig = {}
    for line in res.stdout.splitlines():
        m = re.match(r"^PROBE (\S+) (\S+) (.*)$", line)
        if m:
            p = [float(v) for v in m.group(3).split()]
            sig[(m.group(1), int(m.group(2)))] = [-v for v in p]
    if len(sig) != 13:
        sys.exit(f"lammps printed {len(sig)} probes, expected 13:\n{res.stdout[-3000:]}")
    C = [[(sig[(str(J), 1)][i] - sig[(str(J), -1)][i]) / (2 * up) for J in range(6)] for i in range(6)]
    return C, sig[("ref", 0)]


def run_talus(exe, data, up):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "tensor.txt")
        res = subprocess.run([exe, "-input", os.path.abspath(data), "-probe", "affine", "-probe_jiggle", "0",
                              "-strain", repr(up), "-scratch", os.path.join(tmp, "ref.h5"), "-output", out],
                             capture_output=True, text=True)
        if res.returncode != 0:
            sys.exit(f"elastic_tensor failed: {res.stdout[-2000:]}{res.stderr[-2000:]}")
        with open(out) as f:
            rows = [l for l in f if not l.startswith("#")]
    v = [float(x) for x in rows[0].split()]
    C = [v[6 * i:6 * i + 6] for i in range(6)]
    lines = res.stdout.splitlines()
    summary = next(l for l in lines if l.startswith("summary:"))
    return C, summary


def sym(C):
    return [[0.5 * (C[i][j] + C[j][i]) for j in range(6)] for i in range(6)]


def moduli(C):
    c11 = (C[0][0] + C[1][1] + C[2][2]) / 3
    c12 = (C[0][1] + C[0][2] + C[1][2]) / 3
    c44 = (C[3][3] + C[4][4] + C[5][5]) / 3
    nu = 1 / (1 + c11 / c12)
    g = 0.5 * (c44 + 0.5 * (c11 - c12))
    return {"E": 2 * g * (1 + nu), "nu": nu, "K": (c11 + 2 * c12) / 3, "G1": c44, "G2": 0.5 * (c11 - c12),
            "zener": 2 * c44 / (c11 - c12)}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("data")
    ap.add_argument("--talus", default="build/bin/elastic_tensor")
    ap.add_argument("--lmp", default="lmp")
    ap.add_argument("--strain", type=float, default=1e-6)
    ap.add_argument("--restart", default="",
                    help="also probe this LAMMPS restart of the same state (it keeps the contact histories)")
    ap.add_argument("--compare", default="",
                    help="a stored 6x6 tensor (36 numbers after '#' lines, the authors' stiffness_matrix_sym.txt)")
    a = ap.parse_args()
    if not (0 < a.strain <= 0.1):
        sys.exit(f"--strain {a.strain} outside (0, 0.1]")
    CL, ref = run_lammps(a.lmp, a.data, a.strain)
    CT, summary = run_talus(a.talus, a.data, a.strain)
    SL = sym(CL)
    big = max(abs(v) for r in SL for v in r)
    print(f"LAMMPS reference stress (Pa): " + " ".join(f"{v:.10g}" for v in ref))
    print("entry  LAMMPS (Pa)  Talus (Pa)  difference / largest entry")
    worst = 0.0
    ST = sym(CT)
    for i in range(6):
        for j in range(6):
            d = abs(ST[i][j] - SL[i][j]) / big
            worst = max(worst, d)
            print(f"C{i+1}{j+1} {SL[i][j]:.12g} {ST[i][j]:.12g} {d:.2e}")
    ml, mt = moduli(SL), moduli(ST)
    print("moduli LAMMPS: " + " ".join(f"{k}={v:.8g}" for k, v in ml.items()))
    print("moduli Talus:  " + " ".join(f"{k}={v:.8g}" for k, v in mt.items()))
    extra = ""
    if a.restart:
        CR, _ = run_lammps(a.lmp, a.restart, a.strain, restart=True)
        SR = sym(CR)
        dh = max(abs(SR[i][j] - SL[i][j]) for i in range(6) for j in range(6)) / big
        print(f"LAMMPS on the restart (with contact histories) against LAMMPS on the data file: largest "
              f"difference {dh:.3e} of the largest entry; moduli: " +
              " ".join(f"{k}={v:.8g}" for k, v in moduli(SR).items()))
        extra += f" history_effect={dh:.3e}"
    if a.compare:
        with open(a.compare) as f:
            v = [float(x) for l in f if not l.startswith("#") for x in l.split()]
        if len(v) != 36:
            sys.exit(f"--compare {a.compare}: {len(v)} numbers, expected 36")
        CS = [v[6 * i:6 * i + 6] for i in range(6)]
        print(f"against {a.compare}: entry, stored, LAMMPS-restart, Talus, relative to the largest entry")
        base = SR if a.restart else SL
        wr, wt = 0.0, 0.0
        for i in range(6):
            for j in range(6):
                er = abs(base[i][j] - CS[i][j]) / big
                et = abs(ST[i][j] - CS[i][j]) / big
                # the stored file prints C13 where C32 (= C23) belongs
                note = " (the file holds C13 here)" if (i, j) == (2, 1) else ""
                if not note:
                    wr, wt = max(wr, er), max(wt, et)
                print(f"C{i+1}{j+1} {CS[i][j]:.15g} {base[i][j]:.15g} {ST[i][j]:.15g} {er:.2e} {et:.2e}{note}")
        print("stored moduli: " + " ".join(f"{k}={v:.8g}" for k, v in moduli(CS).items()))
        extra += f" stored_vs_lammps={wr:.3e} stored_vs_talus={wt:.3e}"
    n = re.search(r"n=(\d+)", summary).group(1)
    print(f"summary: n={n} max_rel={worst:.3e} E_talus={mt['E']:.10g} E_lammps={ml['E']:.10g} "
          f"nu_talus={mt['nu']:.8f} nu_lammps={ml['nu']:.8f}{extra}")


if __name__ == "__main__":
    main()
