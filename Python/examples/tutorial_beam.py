"""Tutorial 3 in Python (docs/tutorial/03_beam.c): a beam under its own
weight.  A steel cantilever, 2 m long with a 0.1 m square section, clamped
at y = 0, meshed with 27-node hexahedra and solved quasi-statically under
gravity.  Checks: the deflection along the beam against beam theory
(Euler-Bernoulli for a uniform load, plus Timoshenko's shear term), and the
clamp's reaction against the weight.  Output in out/: beam.xmf (ParaView:
Warp By Vector with "displacement"), deflection.csv
(/usr/bin/python3 docs/tutorial/plot.py out/deflection.csv).
Run: PYTHONPATH=build/python python3 Python/examples/tutorial_beam.py
"""
import os

import numpy as np

import talus

L, b, E, rho, g = 2.0, 0.1, 2e11, 7850.0, 9.81            # m, m, Pa, kg/m^3, m/s^2
mesh = talus.Mesh.box("hex27", (2, 20, 2), (-b / 2, 0, -b / 2), (b / 2, L, b / 2))
steel = talus.Material("hooke", E=E, nu=0.0, density=rho)  # Poisson's ratio 0: beam theory's section
beam = talus.Solid(mesh, steel, fix={"ymin": 7}, gravity=(0, 0, -g))
stepper = talus.Stepper(beam, "quasi_static")              # the default options: talus.parameters("stepper", ...)
stepper.step(1.0)

os.makedirs("out", exist_ok=True)
talus.SolidWriter(beam, "out", "beam").write(stepper)
# beam theory: w(y) = q y^2 (6 L^2 - 4 L y + y^2) / (24 E I) + q (L y - y^2 / 2) / (kappa G A)
q, I, kGA = rho * g * b * b, b**4 / 12, 5.0 / 6.0 * E / 2 * b * b
X = mesh.nodes
axis = np.flatnonzero((np.abs(X[:, 0]) < 1e-12) & (np.abs(X[:, 2]) < 1e-12))   # the nodes on the beam's axis
y = X[axis, 1]
w_fem = -stepper.node_displacements()[axis, 2]
w_theory = q * y * y * (6 * L * L - 4 * L * y + y * y) / (24 * E * I) + q * (L * y - y * y / 2) / kGA
order = np.argsort(y)
np.savetxt("out/deflection.csv", np.column_stack([y, w_fem, w_theory])[order], delimiter=",", comments="",
           header="y [m],w_fem [m],w_theory [m]")
tip = w_fem[y == L][0] / w_theory[y == L][0]
outer = y > 0.25 * L
worst = np.abs(w_fem[outer] / w_theory[outer] - 1).max()
reaction = beam.reactions(stepper)[:, 2].sum() / (q * L)
print(f"tip deflection {tip:.5f} of beam theory's; worst ratio along the outer 3/4: 1 {worst:+.2e}; "
      f"reaction {reaction:.8f} of the weight")
ok = abs(tip - 1) <= 0.002 and worst <= 0.005 and abs(reaction - 1) <= 1e-8
print(f"summary: tip_ratio={tip:.6g} worst_deviation={worst:.3g} reaction_ratio={reaction:.10g} "
      f"status={'ok' if ok else 'failed'}")
assert ok
