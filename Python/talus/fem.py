"""Finite elements: meshes, materials, solids and time steppers.

Meshes come from the structured generator (Mesh.box) or a Gmsh file
(Mesh.read_gmsh).  A Solid borrows its mesh and material (the Python
objects keep them alive).  Node arrays: Mesh.nodes is a view of the
reference coordinates; a Stepper's u, v, a are views of its dof-space
state (clamped components are not dofs); Stepper.node_displacements()
scatters u to nodes (a copy).  A coupled loop (talus.coupling) holds the
node-space displacements and velocities itself, as views.
"""
import ctypes

import numpy as np

from . import _lib
from ._lib import call, cstr, lib, named_settings
from ._views import address, view


def _element_type(name):
    t = ctypes.c_void_p()
    call("tl_element_type_find", cstr(name), ctypes.byref(t))
    return t


class Mesh(_lib.Handle):
    """A mesh: Mesh.box("hex8", (2, 30, 2), lo, hi) (face and node sets
    xmin, xmax, ymin, ymax, zmin, zmax; block "body") or
    Mesh.read_gmsh(path)."""

    def __init__(self, handle):
        self._init_handle("tl_mesh_destroy")
        self._h = handle

    @classmethod
    def box(cls, element="hex8", cells=(1, 1, 1), lo=(0, 0, 0), hi=(1, 1, 1)):
        n = (ctypes.c_size_t * 3)(*[int(c) for c in cells])
        a = (ctypes.c_double * 3)(*[float(v) for v in lo])
        b = (ctypes.c_double * 3)(*[float(v) for v in hi])
        h = ctypes.c_void_p()
        call("tl_mesh_create_box", _element_type(element), n, a, b, ctypes.byref(h))
        return cls(h)

    @classmethod
    def read_gmsh(cls, path):
        h = ctypes.c_void_p()
        call("tl_mesh_read_gmsh", cstr(path), ctypes.byref(h))
        return cls(h)

    def _nodes(self):
        dim, n, x = ctypes.c_int(), ctypes.c_size_t(), ctypes.c_void_p()
        lib.tl_api_mesh_nodes(self._h, ctypes.byref(dim), ctypes.byref(n), ctypes.byref(x))
        return dim.value, n.value, x

    @property
    def n_nodes(self):
        return self._nodes()[1]

    @property
    def dim(self):
        return self._nodes()[0]

    @property
    def nodes(self):
        """Reference coordinates (n_nodes, 3), m; a read-only view."""
        dim, n, x = self._nodes()
        return view(address(x), n, 3, 0, self, readonly=True)

    def node_set(self, name):
        """The sorted node indices of a named node set (a copy)."""
        n, nodes = ctypes.c_size_t(), ctypes.c_void_p()
        call("tl_api_mesh_node_set", self._h, cstr(name), ctypes.byref(n), ctypes.byref(nodes))
        if n.value == 0:
            return np.zeros(0, dtype=np.uint64)
        return np.ctypeslib.as_array((ctypes.c_size_t * n.value).from_address(address(nodes))).copy()

    @property
    def volume(self):
        return lib.tl_mesh_volume(self._h)


class Material(_lib.Handle):
    """A registered material by name with its parameters
    (`talus.types("material")`): Material("hooke", E=1e8, nu=0.0, density=1309)."""

    def __init__(self, name, **params):
        self._init_handle("tl_material_destroy")
        call("tl_material_create", cstr(name), ctypes.byref(self._h))
        for k, v in params.items():
            call("tl_material_set", self._h, cstr(k), float(v))
        call("tl_material_setup", self._h)

    def __getitem__(self, name):
        x = ctypes.c_double()
        call("tl_material_get", self._h, cstr(name), ctypes.byref(x))
        return x.value


class Solid(_lib.Handle):
    """A finite-strain solid on a mesh with one material:
    Solid(mesh, material, fix={"ymin": 7}, gravity=None).  `fix` maps node
    sets to component masks (1 x, 2 y, 4 z).  Set up at construction unless
    setup=False (then add conditions and call setup())."""

    def __init__(self, mesh, material, fix=None, gravity=None, setup=True):
        self.mesh, self.material = mesh, material
        self._init_handle("tl_solid_destroy", borrowed=(mesh, material))
        call("tl_solid_create", mesh._h, ctypes.byref(self._h))
        call("tl_solid_set_material", self._h, None, material._h)
        for name, mask in (fix or {}).items():
            call("tl_solid_fix", self._h, cstr(name), int(mask))
        if gravity is not None:
            g = np.asarray(gravity, dtype=float)
            call("tl_solid_add_gravity", self._h, _lib.Vec3(*g))
        if setup:
            self.setup()

    def setup(self):
        call("tl_solid_setup", self._h)

    def reactions(self, stepper, static=True):
        """The reaction forces at the constrained node components at the
        stepper's state (n_nodes, dim; 0 elsewhere): f_int(u) - f_ext, plus
        M a unless static."""
        t, n, u, v, a = stepper._state()
        out = np.zeros((self.mesh.n_nodes, self.mesh.dim))
        call("tl_solid_reactions", self._h, float(t), ctypes.cast(u, _lib.c_double_p),
             None if static else ctypes.cast(a, _lib.c_double_p), out.ctypes.data_as(_lib.c_double_p))
        return out

    def fix(self, node_set, mask=7):
        call("tl_solid_fix", self._h, cstr(node_set), int(mask))

    @property
    def mass(self):
        return lib.tl_solid_total_mass(self._h)


class Stepper(_lib.Handle):
    """A registered time stepper over a solid (`talus.types("stepper")`:
    newmark, central_difference, quasi_static) with the library's default
    options and the numeric ones given, each a parameter of the type
    (`talus.parameters("stepper", type)`: e.g. keep_factors=1, rtol=1e-8
    for newmark, blowup for central_difference; another name, a value out
    of range or a fraction for an integer is refused) and a linear solver
    by name.  The state
    starts at rest at t = 0."""

    def __init__(self, solid, type="newmark", solver=None, **options):
        self.solid = solid
        self._init_handle("tl_stepper_destroy", borrowed=(solid,))
        n, names, values = named_settings(options)
        call("tl_api_stepper_create", cstr(type), lib.tl_solid_system(solid._h), cstr(solver), n, names, values,
             ctypes.byref(self._h))
        self.set_state(0.0)

    def set_state(self, t=0.0, u=None, v=None):
        """Time and dof-space state (None: zero); the acceleration follows."""
        def ptr(a):
            return None if a is None else np.ascontiguousarray(a, dtype=np.float64).ctypes.data_as(_lib.c_double_p)
        call("tl_stepper_set_state", self._h, float(t), ptr(u), ptr(v))

    def step(self, dt):
        call("tl_stepper_step", self._h, float(dt))

    def critical_timestep(self):
        dt = ctypes.c_double()
        call("tl_stepper_critical_dt", self._h, ctypes.byref(dt))
        return dt.value

    def _state(self):
        t, n = ctypes.c_double(), ctypes.c_size_t()
        u, v, a = ctypes.c_void_p(), ctypes.c_void_p(), ctypes.c_void_p()
        lib.tl_api_stepper_state(self._h, ctypes.byref(t), ctypes.byref(n), ctypes.byref(u), ctypes.byref(v),
                                 ctypes.byref(a))
        return t.value, n.value, u, v, a

    time = property(lambda self: self._state()[0])
    u = property(lambda self: view(address(self._state()[2]), self._state()[1], 1, 0, self),
                 doc="dof-space displacements (view)")
    v = property(lambda self: view(address(self._state()[3]), self._state()[1], 1, 0, self),
                 doc="dof-space velocities (view)")
    a = property(lambda self: view(address(self._state()[4]), self._state()[1], 1, 0, self),
                 doc="dof-space accelerations (view)")

    def node_displacements(self):
        """Node-space displacements (n_nodes, 3), clamped components 0 (a copy)."""
        out = np.zeros((self.solid.mesh.n_nodes, 3))
        t, n, u, v, a = self._state()
        lib.tl_solid_dofs_to_nodes(self.solid._h, ctypes.cast(u, _lib.c_double_p),
                                   out.ctypes.data_as(_lib.c_double_p))
        return out

    def node_velocities(self):
        """Node-space velocities (n_nodes, 3), clamped components 0 (a copy)."""
        out = np.zeros((self.solid.mesh.n_nodes, 3))
        t, n, u, v, a = self._state()
        lib.tl_solid_dofs_to_nodes(self.solid._h, ctypes.cast(v, _lib.c_double_p),
                                   out.ctypes.data_as(_lib.c_double_p))
        return out

    def energies(self):
        e = _lib.Energies()
        call("tl_stepper_energies", self._h, ctypes.byref(e))
        return {name: getattr(e, name) for name, _ in _lib.Energies._fields_}
