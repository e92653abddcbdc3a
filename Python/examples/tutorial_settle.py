"""Tutorial (2) in Python: a packing settling on a triangulated floor.

Polydisperse spheres poured on a jittered lattice into a box whose floor is
a triangulated rectangle and whose sides are planes; under gravity they
fall, bounce and settle.  The script checks what a settled packing must
show: the floor carries its weight, the kinetic energy has gone and the
energy balance (dissipation included) holds.  Run: python3 tutorial_settle.py;
in ParaView open settle/particles.xmf, Glyph: Sphere, scale by radius, factor 2.
"""
import numpy as np

import talus

n, box, height = 150, 0.02, 0.05          # particles; box width and height (m)
d_min, d_max, density, g = 2.5e-3, 3.5e-3, 2500.0, 9.81

world = talus.World(box=([0, 0, 0], [box, box, height]), gravity=(0, 0, -g))
grains = world.add_species("grains", density, 0.5 * d_min, 0.5 * d_max)
# linear spring-dashpot k_n = E d_mean with a soft E = 2 MPa, restitution 0.5, Coulomb mu = 0.5
world.add_law(talus.ContactLaw("linear", "coulomb", k_n=2e6 * 0.5 * (d_min + d_max), restitution=0.5, mu=0.5))
floor = world.add_wall(talus.Wall.rectangle(lo=(0, 0), size=(box, box), z=0.0, cells=(4, 4)))  # 64 triangles
sides = [world.add_wall(talus.Wall.plane(p, nrm)) for p, nrm in
         (((0, 0, 0), (1, 0, 0)), ((box, 0, 0), (-1, 0, 0)), ((0, 0, 0), (0, 1, 0)), ((0, box, 0), (0, -1, 0)))]

# pour: a jittered lattice of pitch 1.05 d_max from the top down, small random velocities
rng = np.random.default_rng(1)
pitch = 1.05 * d_max
side = int((box - pitch) // pitch)
k = np.arange(n)
x = np.column_stack([pitch * (1 + k % side**2 % side), pitch * (1 + k % side**2 // side),
                     height - pitch * (1 + k // side**2)])
x[:, :2] += 0.02 * pitch * (rng.random((n, 2)) - 0.5)
v = np.column_stack([0.05 * (rng.random((n, 2)) - 0.5), np.zeros(n)])
world.add_particles(x, radius=0.5 * (d_min + (d_max - d_min) * rng.random(n)), v=v, species=grains)

world.timestep = 0.2 * world.critical_timestep()
world.track_energy()
world.setup()
e0, weight = world.energy()["total"], g * world.mass.sum()
snapshots = talus.ParticleWriter("settle", "particles")   # ParaView: open settle/particles.xmf
snapshots.write(world)
chunk = int(0.02 / world.timestep)
for _ in range(15):                         # 0.3 s
    world.step(chunk)
    snapshots.write(world)
    e = world.energy()
    print(f"t = {world.time:.3f} s  kinetic = {e['kinetic_translational']:.3e} J  "
          f"floor carries {-floor.account['force'][2] / weight:.3f} of the weight")

e = world.energy()
z, _ = world.coordination()
carried = -floor.account["force"][2] / weight      # the force the grains exert on the floor, over their weight
walls = -sum(w.account["force"][2] for w in [floor] + sides) / weight    # friction lets the sides hold some
drift = abs(e["total"] - e0) / abs(e0)
print(f"summary: n={world.n} time={world.time:.4g} floor_load_over_weight={carried:.4f} walls_load_over_weight={walls:.6f} "
      f"kinetic={e['kinetic_translational']:.3e} coordination={z:.3f} energy_drift={drift:.2e} "
      f"lowest_z={world.x[:, 2].min():.3e}")
assert abs(walls - 1.0) < 1e-3, walls              # a settled packing rests on its walls
assert carried > 0.9, carried                      # most of it on the triangulated floor
assert e["kinetic_translational"] < 1e-4 * weight * d_max, e["kinetic_translational"]
assert drift < 1e-2, drift                         # total counts the dissipated energy
assert z > 3.0, z                                  # a packing, not a gas
assert world.x[:, 2].min() > 0.0                   # nobody fell through the triangles
