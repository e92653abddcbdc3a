"""Tutorial 2 in Python (docs/tutorial/02_settling.c): a packing settling on
a triangulated floor.  200 frictional grains drop into a box whose floor is
a triangulated surface and whose sides are planes, and come to rest.
Checks: the grains stop (kinetic energy down to a millionth of the
potential energy released) and the walls carry the whole weight.
Output in out/: particles.xmf and walls.xmf (open both in ParaView;
particles: Glyph, Sphere, scale by radius, factor 2), settling.csv
(/usr/bin/python3 docs/tutorial/plot.py out/settling.csv kinetic wall_load weight).
Run: PYTHONPATH=build/python python3 Python/examples/tutorial_settle.py
"""
import os

import numpy as np

import talus

r, L, g = 0.005, 0.06, 9.81                               # m, m, m/s^2
world = talus.World(box=([0, 0, 0], [L, L, 0.1]), gravity=(0, 0, -g))   # the box: where planes are drawn
sand = world.add_species("sand", 2500.0, 0.8 * r, r)
rng = np.random.default_rng(1)
i = np.arange(200)                                        # a jittered 5 x 5 x 8 lattice
x = np.column_stack([(i % 5 + 0.5) * L / 5, (i // 5 % 5 + 0.5) * L / 5, 0.01 + (i // 25) * 2.4 * r])
x[:, :2] += 0.2 * r * (rng.random((200, 2)) - 0.5)
world.add_particles(x, radius=0.5 * (1.6 * r + 0.4 * r * rng.random(200)), species=sand)  # uniform in diameter
world.add_law(talus.ContactLaw("linear", "coulomb", k_n=2000.0, restitution=0.3, mu=0.4))
world.add_wall(talus.Wall.rectangle(lo=(0, 0), size=(L, L), z=0.0, cells=(8, 8)))  # four triangles a square
for point, normal in (((0, 0, 0), (1, 0, 0)), ((L, 0, 0), (-1, 0, 0)), ((0, 0, 0), (0, 1, 0)), ((0, L, 0), (0, -1, 0))):
    world.add_wall(talus.Wall.plane(point, normal))
walls = [world.wall(k) for k in range(world.n_walls)]
world.timestep = 1e-4
world.setup()

os.makedirs("out", exist_ok=True)
particles, wall_out = talus.ParticleWriter("out", "particles"), talus.WallWriter("out", "walls")
weight, e0 = g * world.mass.sum(), world.energy()["gravitational"]
rows = []
for step in range(20001):
    if step % 500 == 0:
        particles.write(world)
        wall_out.write(world, step)                       # the floor and the four sides
    load = 0.0 - sum(w.account["force"][2] for w in walls)  # the grains push the walls down
    e = world.energy()
    if step % 50 == 0:
        rows.append([world.time, e["kinetic_translational"] + e["kinetic_rotational"], load, weight])
    world.step(1)
np.savetxt("out/settling.csv", rows, delimiter=",", comments="", header="t [s],kinetic [J],wall_load [N],weight [N]")
ke = (e["kinetic_translational"] + e["kinetic_rotational"]) / (e0 - e["gravitational"])
print(f"kinetic energy {ke:.2e} of the energy released; the walls carry {load / weight:.5f} of the weight")
ok = ke <= 1e-6 and abs(load / weight - 1) <= 0.005 and world.x[:, 2].min() > 0
print(f"summary: kinetic_ratio={ke:.3g} load_ratio={load / weight:.6g} status={'ok' if ok else 'failed'}")
assert ok
