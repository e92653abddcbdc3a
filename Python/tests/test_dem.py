"""The DEM world from Python: views without copies, ids, walls."""
import numpy as np
import pytest

import talus

K_N, R, RHO, G = 1e4, 0.01, 2500.0, 9.81


def resting_sphere(gravity=(0, 0, -G)):
    """One sphere of radius R just above a plane floor z = 0 (not touching)."""
    w = talus.World(box=([0, 0, 0], [1, 1, 1]), gravity=gravity)
    w.add_species("g", RHO, R)
    w.add_law(talus.ContactLaw("linear", k_n=K_N))
    floor = w.add_wall(talus.Wall.plane((0, 0, 0), (0, 0, 1)))
    w.add_particle((0.5, 0.5, 2 * R), radius=R)
    w.timestep = 0.1 * w.critical_timestep()
    w.setup()
    return w, floor


def test_position_view_is_the_worlds_memory():
    w, floor = resting_sphere()
    m = w.mass[0]
    assert w.f[0, 2] == pytest.approx(-m * G, rel=1e-14)   # in the air: gravity only
    x = w.x
    assert x.ctypes.data == w.field("x").ctypes.data          # the same memory, not a copy
    delta = 1e-4
    x[0, 2] = R - delta                                        # written through the view ...
    w.compute_forces()                                         # ... the library sees the overlap
    assert w.f[0, 2] == pytest.approx(K_N * delta - m * G, rel=1e-12)
    assert floor.account["force"][2] == pytest.approx(-K_N * delta, rel=1e-12)
    assert floor.account["n_contacts"] == 1


def test_velocity_view_drives_the_step():
    w, _ = resting_sphere(gravity=(0, 0, 0))
    w.v[0] = (0.1, -0.2, 0.0)                                  # write through a temporary view
    x0 = w.x[0].copy()
    w.step(10)
    assert np.allclose(w.x[0] - x0, np.array([0.1, -0.2, 0.0]) * 10 * w.timestep, rtol=1e-9, atol=0)
    e = w.energy()
    assert e["kinetic_translational"] == pytest.approx(0.5 * w.mass[0] * 0.05, rel=1e-12)
    assert np.allclose(e["momentum"], w.mass[0] * np.array([0.1, -0.2, 0.0]), rtol=1e-12)


def test_views_keep_the_world_alive():
    w, _ = resting_sphere()
    x = w.x
    del w                                                      # the view holds the world
    assert x[0, 2] == pytest.approx(2 * R)


def test_ids_follow_particles_through_renumbering():
    w = talus.World(box=([0, 0, 0], [0.1, 0.1, 0.1]), periodic=(1, 1, 1))
    s = w.add_species("g", RHO, 1e-3, 2e-3)
    w.add_law(talus.ContactLaw("linear", k_n=1e3, restitution=0.5))
    rng = np.random.default_rng(3)
    lattice = (np.arange(7) + 0.5) * 0.1 / 7                   # 343 sites 14 mm apart
    x = np.stack(np.meshgrid(lattice, lattice, lattice), axis=-1).reshape(-1, 3)
    n = len(x)
    ids = w.add_particles(x, radius=1e-3 + 1e-3 * rng.random(n),
                          v=rng.normal(size=(n, 3)), species=s)
    radius_of = dict(zip(w.id, w.radius))
    w.sort_interval = 1                                        # renumber at every rebuild
    w.timestep = 0.2 * w.critical_timestep()
    w.set_skin(0.05)
    w.setup()
    w.step(400)
    assert w.stats()["rebuilds"] > 1
    assert not np.array_equal(w.id, ids)                       # renumbered ...
    assert sorted(w.id) == sorted(ids)                         # ... the same particles
    assert all(radius_of[i] == r for i, r in zip(w.id, w.radius))
    k = w.find(ids[7])
    assert w.id[k] == ids[7]


def test_reserve_keeps_views_valid():
    w = talus.World()
    w.add_species("g", RHO, R)
    w.reserve(50)
    w.add_particle((0, 0, 0), radius=R)
    x = w.x
    address = x.ctypes.data
    for k in range(1, 50):
        w.add_particle((3 * R * k, 0, 0), radius=R)
    assert w.x.ctypes.data == address and w.capacity >= 50
    assert w.n == 50 and x.shape == (1, 3)                     # an old view keeps its old length


def test_trisurface_wall_arrays_and_registry():
    tri = talus.Wall.trisurface([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2], [1, 3, 2]],
                                feature_angle=30.0)
    assert tri.vertices.shape == (4, 3) and tri.triangles.tolist() == [[0, 1, 2], [1, 3, 2]]
    with pytest.raises(ValueError):
        tri.vertices[0, 0] = 1.0                               # read-only: moved through set_vertices
    tri.set_vertices(tri.vertices + (0, 0, 0.5))
    assert np.all(tri.vertices[:, 2] == 0.5)
    assert "linear" in talus.types("contact_normal") and "trisurface" in talus.types("wall")
    assert "newmark" in talus.types("stepper") and "hex8" in talus.types("element")


def test_particle_snapshots(tmp_path):
    w, _ = resting_sphere()
    out = talus.ParticleWriter(str(tmp_path / "out"), "particles")
    out.write(w)
    w.step(3)
    out.write(w)
    assert out.count == 2
    assert (tmp_path / "out" / "particles_000001.h5").exists()
    xmf = (tmp_path / "out" / "particles.xmf").read_text()
    assert xmf.count("particles_00000") >= 2           # a time series of both


def test_contacts_balance_gravity():
    """A column of three spheres at rest on a floor: contact forces from the
    library's list, against the weights they carry."""
    w = talus.World(gravity=(0, 0, -G))
    w.add_species("g", RHO, R)
    w.add_law(talus.ContactLaw("linear", k_n=K_N))
    w.add_wall(talus.Wall.plane())
    m = RHO * 4 / 3 * np.pi * R**3
    delta = m * G / K_N                                # each contact's overlap for the weight above it
    z1 = R - 3 * delta
    z2 = z1 + 2 * R - 2 * delta
    z3 = z2 + 2 * R - delta
    for z in (z1, z2, z3):
        w.add_particle((0, 0, z), radius=R)
    w.timestep = 0.1 * w.critical_timestep()
    w.setup()
    c = w.contacts()
    assert len(c["i"]) == 2
    fz = sorted(abs(c["force"][:, 2]))
    assert fz == pytest.approx([m * G, 2 * m * G], rel=1e-9)
    assert np.allclose(np.abs(w.f[:, 2]), 0.0, atol=1e-9 * m * G)   # every sphere in balance
