"""Scenes from files from Python (particles from LAMMPS data files and HDF5
snapshots, triangulated walls from STL files, solids from Gmsh meshes), the
volume-coupled loop, and the errors of each as TalusError with the
library's message."""
import math

import numpy as np
import pytest

import talus

LAMMPS_DATA = """LAMMPS data file: three spheres
3 atoms
2 atom types
0 1 xlo xhi
0 1 ylo yhi
0 1 zlo zhi

Atoms # sphere

1 1 0.02 2500 0.1 0.2 0.3
2 2 0.04 2500 0.5 0.5 0.5
3 1 0.02 2500 0.9 0.8 0.7

Velocities

1 1.0 0 0 0 0 0
2 0 -2.0 0 0 0 0
3 0 0 3.0 0 0 0
"""


def world_with_species(n=2):
    w = talus.World(box=([0, 0, 0], [1, 1, 1]))
    for k in range(n):
        w.add_species(f"s{k}", 2500.0, 0.005, 0.05)
    return w


def test_particles_from_lammps_data(tmp_path):
    path = tmp_path / "three.data"
    path.write_text(LAMMPS_DATA)
    w = world_with_species()
    assert w.add_particles_from_file(str(path)) == 3        # species from the atom types
    order = np.argsort(w.x[:, 0])
    assert np.allclose(w.x[order], [[0.1, 0.2, 0.3], [0.5, 0.5, 0.5], [0.9, 0.8, 0.7]], rtol=0, atol=1e-15)
    assert np.allclose(w.radius[order], [0.01, 0.02, 0.01], rtol=1e-15)   # diameter / 2
    assert np.allclose(w.v[order], [[1, 0, 0], [0, -2, 0], [0, 0, 3]], rtol=0, atol=0)
    assert list(w.species[order]) == [0, 1, 0]                          # type t -> species t - 1
    assert np.allclose(w.mass[order], 2500 * math.pi / 6 * np.array([0.02, 0.04, 0.02]) ** 3, rtol=1e-12)
    w2 = world_with_species()
    assert w2.add_particles_from_file(str(path), species=1) == 3         # one species for all
    assert set(w2.species) == {1}


def test_lammps_data_errors(tmp_path):
    w = world_with_species()
    with pytest.raises(talus.TalusError) as err:
        w.add_particles_from_file(str(tmp_path / "missing.data"))
    assert "missing.data" in err.value.message
    bad = tmp_path / "bad.data"
    bad.write_text(LAMMPS_DATA.replace("2 2 0.04 2500 0.5 0.5 0.5", "2 2 0.04 2500 0.5 zero 0.5"))
    with pytest.raises(talus.TalusError) as err:
        w.add_particles_from_file(str(bad))
    assert "bad.data:11:" in err.value.message and "zero" in err.value.message   # file, line and value named
    assert w.n == 0                                                             # nothing half-added
    one = world_with_species(1)                                                 # type 2 has no species
    with pytest.raises(talus.TalusError) as err:
        good = tmp_path / "three.data"
        good.write_text(LAMMPS_DATA)
        one.add_particles_from_file(str(good))
    assert "species" in err.value.message


def test_particles_from_hdf5_snapshot(tmp_path):
    src = world_with_species()
    src.add_particles(np.array([[0.2, 0.2, 0.2], [0.6, 0.4, 0.3]]), radius=[0.01, 0.03], v=[[0, 0, 1], [1, 0, 0]],
                      species=1)
    writer = talus.ParticleWriter(str(tmp_path), "packing")
    writer.write(src, step=0)
    del writer
    dst = world_with_species()
    assert dst.add_particles_from_file(str(tmp_path / "packing_000000.h5")) == 2
    a, b = np.argsort(src.x[:, 0]), np.argsort(dst.x[:, 0])
    assert np.array_equal(dst.x[b], src.x[a]) and np.array_equal(dst.radius[b], src.radius[a])
    assert np.array_equal(dst.v[b], src.v[a]) and list(dst.species[b]) == [1, 1]
    garbage = tmp_path / "garbage.h5"
    garbage.write_bytes(b"\x89HDF\r\n\x1a\n" + b"\0" * 64)                     # the signature, nothing else
    with pytest.raises(talus.TalusError) as err:
        dst.add_particles_from_file(str(garbage))
    assert "garbage.h5" in err.value.message


# A square of side 100 (mm) in z = 0, two facets, normal +z.
SQUARE_STL = """solid square
facet normal 0 0 1
 outer loop
  vertex 0 0 0
  vertex 100 0 0
  vertex 100 100 0
 endloop
endfacet
facet normal 0 0 1
 outer loop
  vertex 0 0 0
  vertex 100 100 0
  vertex 0 100 0
 endloop
endfacet
endsolid square
"""


def test_wall_from_stl_scaled_and_placed(tmp_path):
    path = tmp_path / "square.stl"
    path.write_text(SQUARE_STL)
    rot = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]                    # 90 degrees about z
    wall = talus.Wall.from_file(str(path), scale=1e-3, rotation=rot, shift=(0.5, 0.0, 0.02))
    x = wall.vertices
    assert x.shape == (4, 3) and wall.triangles.shape == (2, 3)
    assert np.allclose(np.sort(x[:, 0]), [0.4, 0.4, 0.5, 0.5], rtol=0, atol=1e-15)   # x = 0.5 - y
    assert np.allclose(np.sort(x[:, 1]), [0.0, 0.0, 0.1, 0.1], rtol=0, atol=1e-15)
    assert np.all(x[:, 2] == 0.02)
    r = wall.report                                     # what repair found: an open square, one hole of 4 edges
    assert not r["closed"] and r["holes"] == 1 and r["boundary_edges"] == 4 and r["triangles_removed"] == 0
    # a grain resting on it: the wall carries its weight
    w = talus.World(box=([0.3, -0.1, 0], [0.6, 0.2, 0.2]), gravity=(0, 0, -9.81))
    w.add_species("g", 2500.0, 0.005)
    w.add_law(talus.ContactLaw("linear", k_n=1e4, restitution=0.2))
    w.add_wall(wall)
    w.add_particle((0.45, 0.05, 0.02 + 0.005), radius=0.005)
    w.timestep = 0.1 * w.critical_timestep()
    w.setup()
    w.step(4000)
    assert wall.account["force"][2] == pytest.approx(-w.mass[0] * 9.81, rel=1e-3)


def test_wall_from_file_errors(tmp_path):
    with pytest.raises(talus.TalusError) as err:
        talus.Wall.from_file(str(tmp_path / "none.stl"))
    assert "none.stl" in err.value.message
    path = tmp_path / "square.stl"
    path.write_text(SQUARE_STL)
    with pytest.raises(talus.TalusError) as err:
        talus.Wall.from_file(str(path), scale=-1.0)
    assert "-1" in err.value.message                                       # the value named
    with pytest.raises(talus.TalusError) as err:
        talus.Wall.from_file(str(path), require_closed=True)
    assert "edge" in err.value.message                                     # the open edge named
    nan = tmp_path / "nan.stl"
    nan.write_text(SQUARE_STL.replace("vertex 100 100 0\n  vertex 0 100 0", "vertex 100 100 0\n  vertex nan 100 0"))
    with pytest.raises(talus.TalusError) as err:
        talus.Wall.from_file(str(nan))
    assert "nan.stl" in err.value.message


# The unit cube as one hex8 in Gmsh's msh 2.2 ASCII: physical surface
# "bottom" (z = 0, a quad) and physical volume "body".
CUBE_MSH22 = """$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
2
2 2 "bottom"
3 1 "body"
$EndPhysicalNames
$Nodes
8
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
5 0 0 1
6 1 0 1
7 1 1 1
8 0 1 1
$EndNodes
$Elements
2
1 3 2 2 1 1 4 3 2
2 5 2 1 1 1 2 3 4 5 6 7 8
$EndElements
"""


def test_gmsh_22_solid_and_errors(tmp_path):
    path = tmp_path / "cube22.msh"
    path.write_text(CUBE_MSH22)
    mesh = talus.Mesh.read_gmsh(str(path))
    assert mesh.n_nodes == 8 and mesh.volume == pytest.approx(1.0, rel=1e-14)
    assert sorted(mesh.node_set("bottom")) == [0, 1, 2, 3]
    solid = talus.Solid(mesh, talus.Material("hooke", E=1e6, nu=0.25, density=1000.0), fix={"bottom": 7},
                        gravity=(0, 0, -9.81))
    st = talus.Stepper(solid, "quasi_static")
    st.step(1.0)
    top = st.node_displacements()[4:, 2]
    assert np.all(top < 0)                                # it sags under its weight
    # a uniaxial column under its weight: top displacement rho g L^2 / (2 E') within a factor 2
    assert -top.mean() == pytest.approx(1000 * 9.81 / (2 * 1e6), rel=1.0)
    bad = tmp_path / "bad.msh"
    bad.write_text(CUBE_MSH22.replace("5 0 0 1", "5 0 0"))
    with pytest.raises(talus.TalusError) as err:
        talus.Mesh.read_gmsh(str(bad))
    assert "bad.msh" in err.value.message
    with pytest.raises(talus.TalusError) as err:
        talus.Mesh.read_gmsh(str(tmp_path / "absent.msh"))
    assert "absent.msh" in err.value.message


def volume_coupled_bar():
    """Tutorial 5 in Python: a bonded chain (y < 10 m) and a hex8 bar (y > 8 m) overlapping on 8 < y < 10."""
    d, E, rho, v0, y0, s = 0.4, 1e8, 1309.0, 0.01, 3.5, 1.2
    c0 = math.sqrt(E / rho)
    bar = talus.Solid(talus.Mesh.box("hex8", (1, 30, 1), (0, 8, 0), (d, 20, d)),
                      talus.Material("hooke", E=E, nu=0.0, density=rho), fix={"ymax": 7}, setup=False)
    w = talus.World()
    sp = w.add_species("chain", 6 * rho / math.pi, d / 2)
    ids = []
    for a in range(25):  # a right-moving pulse: velocity v and strain -v / c0
        y = (a + 0.5) * d
        u = -v0 * s * math.sqrt(math.pi) / (2 * c0) * (1 + math.erf((y - y0) / s))
        w.add_particle((d / 2, y + u, d / 2), v=(0, v0 * math.exp(-((y - y0) / s) ** 2), 0), radius=d / 2, species=sp)
        ids.append(int(w.id[-1]))
        if a > 0:
            w.add_bond(ids[a - 1], ids[a])
    w.add_law(talus.ContactLaw("bonded_linear", k_n=E * d))
    loop = talus.VolumeCoupledLoop(w, bar, zone=(1, 8.0, 10.0), penalty=1.6e9 / d**2)
    w.timestep = 0.05 * d / c0
    w.setup()
    return w, bar, loop, v0, c0


def test_volume_coupled_bar_momentum_exchange():
    w, bar, loop, v0, c0 = volume_coupled_bar()
    assert loop.stepper.time == 0.0 and np.all(loop.u == 0.0)
    largest = 0.0
    for _ in range(40):
        w.step(10)
        d = loop.diag()
        f = np.abs(d["force_fem"]).max()
        largest = max(largest, f)
        # the force on the bar is minus the force on the particles (Eq. 41), step by step
        assert np.abs(d["force_fem"] + d["force_dem"]).max() <= 1e-12 * max(f, 1e-300)
        # the world's particles carry the coupling force the loop reports
        assert np.allclose(w.field("f_coupling").sum(axis=0), d["force_dem"], rtol=1e-12, atol=1e-12 * max(f, 1e-300))
    assert largest > 0.0                                 # the pulse reached the zone: forces were exchanged
    assert loop.diag()["eq41_max"] <= 1e-12
    assert loop.stepper.time == pytest.approx(w.time, rel=1e-12)   # lock-step
    vbar = loop.stepper.node_velocities()[:, 1]
    assert vbar.max() > 0.1 * v0                          # the bar moves with the pulse
    assert np.abs(loop.u).max() > 0.0


def test_volume_coupling_errors():
    bar = talus.Solid(talus.Mesh.box("hex8", (1, 4, 1), (0, 8, 0), (0.4, 12, 0.4)),
                      talus.Material("hooke", E=1e8, nu=0.0, density=1309.0), fix={"ymax": 7}, setup=False)
    w = talus.World()
    w.add_species("g", 2500.0, 0.2)
    w.add_particle((0.2, 7.0, 0.2), radius=0.2)
    with pytest.raises(talus.TalusError) as err:
        talus.VolumeCoupledLoop(w, bar, zone=(3, 8.0, 10.0), penalty=1e10)
    assert "zone axis 3" in err.value.message
    with pytest.raises(talus.TalusError) as err:
        talus.VolumeCoupledLoop(w, bar, zone=(1, 10.0, 8.0), penalty=1e10)
    assert "lo < hi" in err.value.message
    with pytest.raises(talus.TalusError) as err:
        talus.VolumeCoupledLoop(w, bar, zone=(1, 8.0, 10.0), penalty=-1.0)
    assert "penalty epsilon = -1" in err.value.message
    with pytest.raises(talus.TalusError) as err:
        talus.VolumeCoupledLoop(w, bar, zone=(1, 8.0, 10.0), penalty=1e10, stepper="no_such_stepper")
    assert "no_such_stepper" in err.value.message
