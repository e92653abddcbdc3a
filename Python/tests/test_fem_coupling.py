"""Meshes, solids, steppers and the surface coupling from Python."""
import numpy as np
import pytest

import talus

# One unit-cube hex8 in Gmsh's msh 4.1 ASCII: physical volume "body",
# physical surface "bottom" (z = 0).
CUBE_MSH = """$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
2 2 "bottom"
3 1 "body"
$EndPhysicalNames
$Entities
0 0 1 1
1 0 0 0 1 1 0 1 2 0
1 0 0 0 1 1 1 1 1 1 1
$EndEntities
$Nodes
2 8 1 8
2 1 0 4
1
2
3
4
0 0 0
1 0 0
1 1 0
0 1 0
3 1 0 4
5
6
7
8
0 0 1
1 0 1
1 1 1
0 1 1
$EndNodes
$Elements
2 2 1 2
2 1 3 1
1 1 4 3 2
3 1 5 1
2 1 2 3 4 5 6 7 8
$EndElements
"""


def test_gmsh_cube_under_gravity(tmp_path):
    path = tmp_path / "cube.msh"
    path.write_text(CUBE_MSH)
    mesh = talus.Mesh.read_gmsh(str(path))
    assert mesh.n_nodes == 8 and mesh.dim == 3
    assert mesh.volume == pytest.approx(1.0, rel=1e-14)
    bottom = mesh.node_set("bottom")
    assert sorted(mesh.nodes[bottom, 2]) == [0.0] * 4
    solid = talus.Solid(mesh, talus.Material("hooke", E=1e6, nu=0.25, density=1000.0), fix={"bottom": 7},
                        gravity=(0, 0, -9.81))
    assert solid.mass == pytest.approx(1000.0, rel=1e-12)
    st = talus.Stepper(solid, "newmark")
    assert st.u.shape == (12,)                     # 4 free nodes x 3
    u = st.u                                       # a view of the stepper's state
    for _ in range(5):
        st.step(1e-3)
    assert st.time == pytest.approx(5e-3)
    un = st.node_displacements()
    assert np.all(un[bottom] == 0.0)               # clamped
    top = np.setdiff1d(np.arange(8), bottom)
    assert np.all(un[top, 2] < 0.0)                # falling under gravity
    # at the free nodes the view is the stepper's live state
    assert np.allclose(np.sort(u[2::3]), np.sort(un[top, 2]), rtol=0, atol=0)


def test_structured_box_nodes():
    mesh = talus.Mesh.box("hex8", (2, 3, 1), (0, 0, 0), (2, 3, 1))
    assert mesh.n_nodes == 3 * 4 * 2
    assert np.array_equal(np.unique(mesh.nodes[:, 1]), [0, 1, 2, 3])
    assert mesh.volume == pytest.approx(6.0, rel=1e-14)
    with pytest.raises(ValueError):
        mesh.nodes[0, 0] = 1.0                     # reference coordinates are read-only


def coupled_scene(substeps=10):
    """A short S1: a sphere resting on a clamped hex8 beam, surface-coupled."""
    b, h, L, E = 0.8, 0.8, 12.0, 1e8
    mesh = talus.Mesh.box("hex8", (2, 30, 2), (-b / 2, 0, -h / 2), (b / 2, L, h / 2))
    beam = talus.Solid(mesh, talus.Material("hooke", E=E, nu=0.0, density=1309.0), fix={"ymin": 7})
    sc = talus.SurfaceCoupling(beam, exclude=["ymin"])
    r, k_n, g = 0.1, E * 0.2, 9.81
    m = 2e4 * 4 / 3 * np.pi * r**3
    w = talus.World(gravity=(0, 0, -g))
    w.add_species("grain", 2e4, r)
    w.add_law(talus.ContactLaw("linear", k_n=k_n))
    w.add_particle((0.2, 6.0, h / 2 + r - m * g / k_n), v=(0, 0.1, 0), radius=r)
    sc.add_to(w)
    w.timestep = 0.01 * np.pi * np.sqrt(2 * m / k_n)
    w.setup()
    st = talus.Stepper(beam, "newmark", keep_factors=1, reuse=1000, max_iterations=200)
    loop = talus.CoupledLoop(w, beam, st, [sc], substeps=substeps)
    return w, beam, sc, loop, m * g


def test_coupled_scene_energy_and_momentum():
    w, beam, sc, loop, weight = coupled_scene()
    assert w.n_walls == 1 and sc.n_elements > 0
    surface = w.wall(0)                            # the coupling's wall, owned by the world
    assert surface.type == "trisurface" and surface.vertices.shape[1] == 3
    with pytest.raises(IndexError):
        w.wall(1)
    u = loop.u                                     # taken before stepping: a live view
    assert np.all(u == 0.0)
    e = loop.energy()
    e0, scale = e["total"], e["dem_kinetic"] + e["dem_elastic"]
    worst_balance, worst_energy = 0.0, 0.0
    for _ in range(20):
        loop.step(5)
        worst_balance = max(worst_balance, np.abs(loop.forces.sum(axis=0) + loop.wall_force).max() / weight)
        worst_energy = max(worst_energy, abs(loop.energy()["total"] - e0) / scale)
    assert loop.time == pytest.approx(100 * 10 * w.timestep, rel=1e-9)
    assert u.min() < -1e-4 and np.array_equal(u, loop.u)   # the old view sees the new state
    # the wall holds the particle up with about its weight
    assert loop.wall_force[2] == pytest.approx(weight, rel=0.2)
    assert worst_balance < 1e-12                   # coupling forces = - particle-wall forces
    assert worst_energy < 0.02                     # conserved (no damping) to 2 % of the particle's energy
    assert sc.n_contacts == 1
    lowest = surface.vertices[:, 2].min()          # the wall moved with the beam (bottom face at -0.4)
    assert surface.account["n_contacts"] == 1 and lowest < -0.4 - 1e-4


def test_coupling_refusals_are_exceptions():
    w, beam, sc, loop, weight = coupled_scene()
    with pytest.raises(talus.TalusError) as err:
        talus.SurfaceCoupling(beam, exclude=["no_such_face_set"])
    assert "no_such_face_set" in err.value.message
    with pytest.raises(talus.TalusError) as err:
        talus.CoupledLoop(w, beam, loop.stepper, [sc], substeps=2.5)
    assert "substeps = 2.5 is not an integer" in err.value.message


def test_cyclic_garbage_frees_borrowers_first():
    import gc
    for _ in range(3):
        w, beam, sc, loop, weight = coupled_scene()
        loop.step(2)
        beam.cycle = (loop, sc, w)                 # a cycle: the collector finalizes in any order
        loop.cycle = beam
        del w, beam, sc, loop
        assert gc.collect() > 0                    # a borrowed object is freed after its borrowers
