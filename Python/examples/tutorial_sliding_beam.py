"""Tutorial (4) in Python: a particle sliding on a deformable beam through
the surface coupling (the S1 scene of particle_cantilever, one particle).

The beam (hex8, 0.8 x 12 x 0.8 m, clamped at y = 0, E = 100 MPa) is a
finite-strain solid stepped by Newmark; its free faces are one coupled
boundary, a triangulated DEM wall that follows it and passes the contact
forces back.  A frictionless sphere resting on the top face (overlap
m g / k_n) slides along it at 0.1 m/s.  Checks: the sphere slides along
the beam, the beam deflects under it, the coupling forces balance the
particle–wall forces (momentum), and the coupled energy is conserved
(no damping anywhere).  Run: python3 tutorial_sliding_beam.py; plot
sliding_beam.csv, or open sliding/beam.xmf (Warp By Vector: displacement)
and sliding/particles.xmf in ParaView.
"""
import numpy as np

import talus

b, h, L, E, rho = 0.8, 0.8, 12.0, 1e8, 1309.0           # beam (m, Pa, kg/m^3)
d, rho_p, g, vy, y0 = 0.2, 2e4, 9.81, 0.1, 6.0          # particle (m, kg/m^3, m/s^2, m/s, m)
t_end = 2.0                                             # s

mesh = talus.Mesh.box("hex8", cells=(2, 30, 2), lo=(-b / 2, 0, -h / 2), hi=(b / 2, L, h / 2))
beam = talus.Solid(mesh, talus.Material("hooke", E=E, nu=0.0, density=rho), fix={"ymin": 7})
coupling = talus.SurfaceCoupling(beam, exclude=["ymin"], width=0.0)   # every free face; Dirac forces

r, k_n = d / 2, E * d
m = rho_p * 4 / 3 * np.pi * r**3
world = talus.World(gravity=(0, 0, -g))
world.add_species("grain", rho_p, r)
world.add_law(talus.ContactLaw("linear", k_n=k_n))      # no dashpot, no friction
world.add_particle((0.2, y0, h / 2 + r - m * g / k_n), v=(0, vy, 0), radius=r)
coupling.add_to(world)
dt = 0.01 * np.pi * np.sqrt(2 * m / k_n)
world.timestep = dt
world.setup()

stepper = talus.Stepper(beam, "newmark", keep_factors=1, reuse=1000, max_iterations=200)  # modified Newton
loop = talus.CoupledLoop(world, beam, stepper, [coupling], substeps=10)   # FE step 10 dt
e = loop.energy()
e0, scale = e["total"], e["dem_kinetic"] + e["dem_elastic"]  # the particle's kinetic and contact energy
u = loop.u                                              # a live view: the loop updates it in place
below = np.argmin(np.linalg.norm(mesh.nodes - (0.2, y0, h / 2), axis=1))  # the top node under the start
X = mesh.nodes
lines = [np.flatnonzero((X[:, 2] == h / 2) & (X[:, 0] == x)) for x in (0.0, 0.4)]  # top edges beside x = 0.2
rows, balance, gap = [], 0.0, 0.0
beam_out, particles_out = talus.SolidWriter(beam, "sliding", "beam"), talus.ParticleWriter("sliding", "particles")
while loop.time < t_end:
    loop.step(10)
    if len(rows) % 10 == 0:                             # ParaView: sliding/beam.xmf and sliding/particles.xmf
        beam_out.write(stepper), particles_out.write(world)
    e = loop.energy()
    f_sum = loop.forces.sum(axis=0)                     # coupling forces on the beam's nodes, N
    balance = max(balance, np.abs(f_sum + loop.wall_force).max() / (m * g))
    p = world.x[0]
    surface = h / 2 + np.mean([np.interp(p[1], X[n, 1], u[n, 2]) for n in lines])  # top face under it
    gap = max(gap, abs(p[2] - r - surface))
    rows.append([loop.time, *p, u[below, 2], e["total"] - e0])
rows = np.array(rows)
np.savetxt("sliding_beam.csv", rows, delimiter=",", header="t_s,x_m,y_m,z_m,uz_below_start_m,energy_change_J")
t, y, z = rows[:, 0], rows[:, 2], rows[:, 3]
drift = np.abs(rows[:, 5]).max() / scale
print(f"summary: t={t[-1]:.4g} y={y[-1]:.5g} z={z[-1]:.5g} uz_min={rows[:, 4].min():.4e} "
      f"gap_max={gap:.3e} contacts={coupling.n_contacts} momentum_balance={balance:.2e} energy_drift={drift:.2e}")
assert np.all(np.diff(y) > 0) and y[-1] - y0 > 0.95 * vy * t[-1], y[-1]   # it slides on (downhill: faster)
assert abs(world.x[0, 0] - 0.2) < 0.02                  # along the beam (it twists: off-centre load)
assert gap < 20 * m * g / k_n, gap                      # on the deflected surface: overlap m g / k_n = 4e-5 m
assert coupling.n_contacts >= 1
assert rows[:, 4].min() < -1e-4                         # the beam sags under it
assert np.all(u[mesh.node_set("ymin")] == 0.0)          # the clamp holds
assert balance < 1e-9, balance                          # forces on the beam = - forces on the particle
assert drift < 0.05, drift                              # energy kept by the coupled loop
