"""Tutorial 4 in Python (docs/tutorial/04_sliding.c): a particle sliding on a
deformable beam (surface coupling).  A heavy grain slides without friction
along the top of an elastic, weightless cantilever (hex8, clamped at
y = 0); the beam's free surface is a wall of the DEM world, moved with the
beam, and the contact forces load the beam through its SCoupling elements
(Dirac limit, c = 0).  Checks: the force on the beam is minus the force on
the grain at every step, the coupled energy (grain + beam) is kept, the
beam bends under the grain.  Output in out/: particles.xmf, beam.xmf
(Warp By Vector: displacement), walls.xmf (the beam's surface as the grain
sees it), sliding.csv (/usr/bin/python3 docs/tutorial/plot.py out/sliding.csv tip_w energy).
Run: PYTHONPATH=build/python python3 Python/examples/tutorial_sliding_beam.py
"""
import os

import numpy as np

import talus

r, k_n, v0, g = 0.1, 2e7, 3.0, 9.81                       # m, N/m, m/s, m/s^2
mesh = talus.Mesh.box("hex8", cells=(2, 12, 2), lo=(-0.4, 0, -0.4), hi=(0.4, 4.8, 0.4))
beam = talus.Solid(mesh, talus.Material("hooke", E=1e8, nu=0.0, density=1309.0), fix={"ymin": 7})
coupling = talus.SurfaceCoupling(beam, exclude=["ymin"])  # every boundary face but the clamped end

world = talus.World(gravity=(0, 0, -g))
steel = world.add_species("steel", 2e4, r)
m = 2e4 * 4 / 3 * np.pi * r**3                            # kg
world.add_particle((0, 0.4, 0.4 + r - m * g / k_n), v=(0, v0, 0), radius=r, species=steel)
world.add_law(talus.ContactLaw("linear", k_n=k_n))
coupling.add_to(world)                                    # the beam's surface becomes a wall of law 0
world.timestep = 0.02 * np.pi * np.sqrt(m / k_n)
world.setup()
stepper = talus.Stepper(beam, "central_difference")
loop = talus.CoupledLoop(world, beam, stepper, [coupling])  # one FEM step per DEM step

os.makedirs("out", exist_ok=True)
particles, beam_out = talus.ParticleWriter("out", "particles"), talus.SolidWriter(beam, "out", "beam")
wall_out = talus.WallWriter("out", "walls")
e0, ke0 = loop.energy()["total"], 0.5 * m * v0**2
u, forces = loop.u, loop.forces                           # live views: the loop updates them in place
balance = drift = tip_min = 0.0
rows, step = [], 0
while world.x[0, 1] < 4.0:
    loop.step()
    step += 1
    total = forces.sum(axis=0) + loop.wall_force          # on the beam's nodes + on the grain
    balance = max(balance, np.linalg.norm(total) / (m * g))
    e = loop.energy()["total"]
    drift = max(drift, abs(e - e0) / ke0)
    tip_min = min(tip_min, u[-1, 2])                      # the last node is at the free end
    if step % 20 == 0:
        rows.append([loop.time, world.x[0, 1], u[-1, 2], e])
    if step % 500 == 0:
        particles.write(world), beam_out.write(stepper, step), wall_out.write(world, step)
np.savetxt("out/sliding.csv", rows, delimiter=",", comments="", header="t [s],y [m],tip_w [m],energy [J]")
# against the static deflection under the grain's weight at the free end, m g L^3 / (3 E I)
tip = -tip_min / (m * g * 4.8**3 / (3 * 1e8 * 0.8**4 / 12))
print(f"force balance beam + grain {balance:.2e} of the weight, energy drift {drift:.2e} of the grain's kinetic "
      f"energy, largest tip deflection {tip:.3f} of the static one under the grain at the free end")
ok = balance <= 1e-12 and drift <= 1e-3 and 0.3 <= tip <= 1.5
print(f"summary: force_balance={balance:.3g} energy_drift={drift:.3g} tip_ratio={tip:.4g} "
      f"status={'ok' if ok else 'failed'}")
assert ok
