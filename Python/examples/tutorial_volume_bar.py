"""Tutorial 5 in Python (docs/tutorial/05_volume_bar.c): a volume-coupled
bar.  A chain of bonded particles (y < 10 m) and a hex8 bar (y > 8 m)
overlap on 8 < y < 10, where the Arlequin weights hand the bar from one
model to the other and a penalty ties the particles' homogenised
displacement to the elements' (VolumeCoupledLoop).  A compression pulse
leaves the particles and must arrive in the elements at the speed of sound
sqrt(E / rho), unharmed.  Checks: the arrival time and amplitude at
y = 16.4 m, and the coupling forces' balance (Eq. 41) at every step.
Output in out/: particles.xmf, bar.xmf, pulse.csv.
Run: PYTHONPATH=build/python python3 Python/examples/tutorial_volume_bar.py
"""
import math
import os

import numpy as np

import talus

d, E, rho, v0, y0, s = 0.4, 1e8, 1309.0, 0.01, 3.5, 1.2   # m, Pa, kg/m^3, m/s, m, m
c0 = math.sqrt(E / rho)
mesh = talus.Mesh.box("hex8", (1, 30, 1), (0, 8, 0), (d, 20, d))
bar = talus.Solid(mesh, talus.Material("hooke", E=E, nu=0.0, density=rho), fix={"ymax": 7}, setup=False)

world = talus.World()                   # the chain: k_n = E d and rho_g = 6 rho / pi give sqrt(E / rho)
chain = world.add_species("chain", 6 * rho / math.pi, d / 2)
ids = []
for a in range(25):                     # a right-moving pulse: velocity v and strain -v / c0
    y = (a + 0.5) * d
    u = -v0 * s * math.sqrt(math.pi) / (2 * c0) * (1 + math.erf((y - y0) / s))
    world.add_particle((d / 2, y + u, d / 2), v=(0, v0 * math.exp(-((y - y0) / s) ** 2), 0), radius=d / 2,
                       species=chain)
    ids.append(int(world.id[-1]))
    if a > 0:
        world.add_bond(ids[a - 1], ids[a])
world.add_law(talus.ContactLaw("bonded_linear", k_n=E * d))
loop = talus.VolumeCoupledLoop(world, bar, zone=(1, 8.0, 10.0), penalty=1.6e9 / d**2)   # sets the bar up
world.timestep = 0.05 * d / c0
world.setup()

os.makedirs("out", exist_ok=True)
particles, bar_out = talus.ParticleWriter("out", "particles"), talus.SolidWriter(bar, "out", "bar")
probe = int(np.flatnonzero(np.abs(mesh.nodes[:, 1] - 16.4) < 1e-9)[0])   # a node at y = 16.4 m
at7 = ids[17]                           # the particle at y = 7 m, by its id: the world may renumber its arrays
rows, v_peak, t_peak, step = [], 0.0, 0.0, 0
while world.time < 0.055:
    world.step(1)                       # the bar steps with the world
    v = loop.stepper.node_velocities()[probe, 1]
    if v > v_peak:
        v_peak, t_peak = v, world.time
    rows.append([world.time, world.v[world.find(at7), 1], v])
    if step % 20 == 0:
        particles.write(world)
        bar_out.write(loop.stepper, step)
    step += 1
np.savetxt("out/pulse.csv", rows, delimiter=",", comments="", header="t [s],v_particle_7m [m/s],v_bar_16.4m [m/s]")
t_ratio, v_ratio, eq41 = t_peak / ((16.4 - y0) / c0), v_peak / v0, loop.diag()["eq41_max"]
print(f"pulse at y = 16.4 m: arrival {t_ratio:.4f} of (16.4 - 3.5) / sqrt(E / rho), amplitude {v_ratio:.3f} of the "
      f"sent one; Eq. 41 defect {eq41:.1e}")
ok = abs(t_ratio - 1) <= 0.03 and 0.8 <= v_ratio <= 1.05 and eq41 <= 1e-12
print(f"summary: arrival_ratio={t_ratio:.5g} amplitude_ratio={v_ratio:.4g} eq41={eq41:.3g} "
      f"status={'ok' if ok else 'failed'}")
assert ok
