"""The DEM world: particles, contact laws, walls, stepping.

Particle arrays are numpy views of the library's own arrays (no copy):
writing through `world.x` moves the particles.  A view becomes invalid
  - after an insertion that grows the store beyond its capacity (the arrays
    are reallocated: the old view then points to freed memory), and
  - after a renumbering: the world sorts particles in grid order every few
    neighbour-list rebuilds during `step` (and a removal moves the last
    particle into the hole), so row k of an old view may hold another
    particle.
Take fresh views (the properties build a new one at every access, which
costs a few microseconds) after `add_particle`, `remove_particle` and
`step`; or call `reserve(n)` before inserting and `sort_interval = 0`
to keep indices fixed.  `id` names a particle whatever its index.
"""
import ctypes

import numpy as np

from . import _lib
from ._lib import Vec3, call, cstr, lib
from ._views import address, view

MOTION = {"free": 0, "fixed": 1, "prescribed": 2}


def _vec3(a):
    a = np.asarray(a, dtype=float).reshape(3)
    return Vec3(a[0], a[1], a[2])


def _check_owned(obj):
    if obj._owner is not None:
        raise _lib.TalusError(9, "invalid state", f"this {type(obj).__name__} already belongs to a world")


class ContactLaw(_lib.Handle):
    """A contact law composed of registered parts, by name, with its
    parameters: ContactLaw("linear", "coulomb", k_n=2e5, restitution=0.5,
    mu=0.5).  `talus.types("contact_normal")` lists the normal parts
    (kinds contact_friction, contact_rolling, contact_adhesion the others)."""

    def __init__(self, normal, friction=None, rolling=None, adhesion=None, **params):
        self._init_handle("tl_contact_law_destroy")
        call("tl_contact_law_create", cstr(normal), cstr(friction), cstr(rolling), cstr(adhesion),
             ctypes.byref(self._h))
        for k, v in params.items():
            call("tl_contact_law_set", self._h, cstr(k), float(v))
        call("tl_contact_law_setup", self._h)

    def __getitem__(self, name):
        x = ctypes.c_double()
        call("tl_contact_law_get", self._h, cstr(name), ctypes.byref(x))
        return x.value

    def __setitem__(self, name, value):
        """Sets a parameter and sets the law up again (before it is given to a world)."""
        _check_owned(self)
        call("tl_contact_law_set", self._h, cstr(name), float(value))
        call("tl_contact_law_setup", self._h)


class Wall(_lib.Handle):
    """A wall of any registered type by name with its parameters
    (`talus.types("wall")`): Wall("plane", point_z=0.0, normal_z=1.0).
    Builders: Wall.plane, Wall.trisurface, Wall.rectangle.  Once added to a
    world (World.add_wall) the world owns it; the Python object stays a
    handle to it (its `account`) while the world lives."""

    def __init__(self, type, **params):
        self._init_handle("tl_wall_destroy")
        settings = (_lib.WallSetting * max(len(params), 1))(
            *[_lib.WallSetting(cstr(k), float(v)) for k, v in params.items()])
        call("tl_wall_create", cstr(type), len(params), settings, ctypes.byref(self._h))
        self.type = type

    @classmethod
    def plane(cls, point=(0, 0, 0), normal=(0, 0, 1), velocity=(0, 0, 0)):
        """An infinite plane through `point`; particles live on the side `normal` points to."""
        p, n, v = (np.asarray(a, dtype=float).reshape(3) for a in (point, normal, velocity))
        return cls("plane", point_x=p[0], point_y=p[1], point_z=p[2], normal_x=n[0], normal_y=n[1],
                   normal_z=n[2], velocity_x=v[0], velocity_y=v[1], velocity_z=v[2])

    @classmethod
    def trisurface(cls, vertices, triangles, **params):
        """A triangulated surface: vertices (n, 3) in m, triangles (m, 3)
        vertex indices listed counter-clockwise seen from the + side;
        parameters of the type "trisurface" (corrections, feature_angle, ...)."""
        x = np.ascontiguousarray(vertices, dtype=np.float64).reshape(-1, 3)
        t = np.ascontiguousarray(triangles, dtype=np.intc).reshape(-1, 3)
        s = ctypes.c_void_p()
        call("tl_trisurface_create", x.shape[0], x.ctypes.data_as(_lib.c_double_p), t.shape[0],
             t.ctypes.data_as(_lib.c_int_p), ctypes.byref(s))
        return cls._with_surface(s, params)

    @classmethod
    def rectangle(cls, lo, size, z=0.0, cells=(1, 1), pattern=2, **params):
        """A flat rectangle in the plane z over [lo, lo + size] (x, y),
        cells[0] x cells[1] squares, each split by `pattern` (0: one
        diagonal, 1: alternating diagonals, 2: four triangles around its
        centre); normal +z."""
        s = ctypes.c_void_p()
        call("tl_trisurface_create_rectangle", float(lo[0]), float(lo[1]), float(size[0]), float(size[1]),
             float(z), int(cells[0]), int(cells[1]), int(pattern), ctypes.byref(s))
        return cls._with_surface(s, params)

    @classmethod
    def _with_surface(cls, s, params):
        try:
            w = cls("trisurface", **params)
        except Exception:
            lib.tl_trisurface_destroy(ctypes.byref(s))
            raise
        call("tl_wall_trisurface_set_surface", w._h, s)  # the wall owns the surface, also on failure
        return w

    @classmethod
    def from_file(cls, path, scale=1.0, rotation=None, shift=(0, 0, 0), repair=True, require_closed=False,
                  **params):
        """A triangulated wall from an STL (ASCII or binary) or Gmsh surface
        file, placed as x <- rotation (scale x) + shift: scale 1e-3 for a
        file in millimetres, rotation a 3 x 3 rotation matrix (None: none),
        shift in m.  A defective surface is repaired (repair=True) or
        refused naming the facet; require_closed refuses an open one.
        `report` tells what repair found and did.  Parameters of the type
        "trisurface" (corrections, feature_angle, ...) as for Wall()."""
        rot = None
        if rotation is not None:
            rot = np.ascontiguousarray(rotation, dtype=np.float64).reshape(9)
        sh = np.ascontiguousarray(shift, dtype=np.float64).reshape(3)
        rep = (ctypes.c_double * 9)()
        h = ctypes.c_void_p()
        call("tl_api_wall_from_file", cstr(path), float(scale),
             None if rot is None else rot.ctypes.data_as(_lib.c_double_p), sh.ctypes.data_as(_lib.c_double_p),
             int(bool(repair)), int(bool(require_closed)), ctypes.byref(h), rep)
        w = cls.__new__(cls)
        w._init_handle("tl_wall_destroy")
        w._h = h
        w.type = "trisurface"
        keys = ("vertices_merged", "triangles_removed", "triangles_flipped", "vertices_split", "nonmanifold_edges",
                "holes", "boundary_edges", "closed")
        w.report = {k: int(rep[i]) for i, k in enumerate(keys)}
        w.report["closed"] = bool(w.report["closed"])
        w.report["volume"] = rep[8]
        for k, v in params.items():
            setter = {"corrections": "tl_wall_trisurface_set_corrections",
                      "brute_force": "tl_wall_trisurface_set_brute_force",
                      "feature_angle": "tl_wall_trisurface_set_feature_angle",
                      "drift": "tl_wall_trisurface_set_drift"}.get(k)
            if setter is None:
                raise _lib.TalusError(1, "invalid argument", f"Wall.from_file has no setting '{k}' (settings: "
                                      "corrections, brute_force, feature_angle, drift)")
            call(setter, w._h, float(v) if k == "feature_angle" else int(v))
        return w

    def _surface_arrays(self):
        if self.type != "trisurface":  # its own type name: a trisurface wall made by the coupling too
            raise _lib.TalusError(10, "unsupported", f"a wall of type {self.type} has no vertices")
        s = lib.tl_wall_trisurface_surface(self._h)
        x, v, t = ctypes.c_void_p(), ctypes.c_void_p(), ctypes.c_void_p()
        nv, nt = ctypes.c_size_t(), ctypes.c_size_t()
        lib.tl_api_trisurface_arrays(s, ctypes.byref(x), ctypes.byref(v), ctypes.byref(nv), ctypes.byref(t),
                                     ctypes.byref(nt))
        return s, x, v, nv.value, t, nt.value

    @property
    def vertices(self):
        """Vertex positions (n, 3), a read-only view: move them with set_vertices."""
        s, x, v, nv, t, nt = self._surface_arrays()
        return view(address(x), nv, 3, 0, self, readonly=True)

    @property
    def triangles(self):
        s, x, v, nv, t, nt = self._surface_arrays()
        return view(address(t), nt, 3, 2, self, readonly=True)

    def set_vertices(self, x, v=None):
        """Moves a triangulated wall: positions (n, 3) and velocities (n, 3)
        or None; normals, boxes and edge shapes are recomputed."""
        s = self._surface_arrays()[0]
        x = np.ascontiguousarray(x, dtype=np.float64)
        vp = None if v is None else np.ascontiguousarray(v, dtype=np.float64)
        call("tl_trisurface_set_vertices", s, x.ctypes.data_as(_lib.c_double_p),
             None if vp is None else vp.ctypes.data_as(_lib.c_double_p))

    @property
    def account(self):
        """The last step's force and torque (about the origin) the particles
        exert on the wall, its contact count, stored elastic energy and the
        work its prescribed motion did (the last two tracked with
        World.track_energy)."""
        f, t = (ctypes.c_double * 3)(), (ctypes.c_double * 3)()
        n, e, w = ctypes.c_size_t(), ctypes.c_double(), ctypes.c_double()
        lib.tl_api_wall_account(self._h, f, t, ctypes.byref(n), ctypes.byref(e), ctypes.byref(w))
        return {"force": np.array(f[:]), "torque": np.array(t[:]), "n_contacts": n.value,
                "elastic_energy": e.value, "work": w.value}


class World(_lib.Handle):
    """A DEM world (tl_dem.h).

    w = World(box=([0, 0, 0], [1, 1, 1]), gravity=(0, 0, -9.81))
    s = w.add_species("grain", density=2500, r_min=1e-3, r_max=1.5e-3)
    w.add_law(ContactLaw("linear", "coulomb", k_n=1e4, restitution=0.5, mu=0.5))
    w.add_wall(Wall.plane())
    w.add_particle((0.5, 0.5, 0.1), radius=1e-3, species=s)
    w.timestep = 0.2 * w.critical_timestep()
    w.setup(); w.step(1000)
    """

    def __init__(self, box=None, periodic=None, gravity=None, dimension=3):
        self._init_handle("tl_dem_destroy")
        call("tl_dem_create", ctypes.byref(self._h))
        self._p = lib.tl_dem_particles(self._h)
        self._gravity = np.zeros(3)
        if dimension != 3:
            call("tl_dem_set_dimension", self._h, int(dimension))
        if box is not None:
            self.set_box(box[0], box[1], periodic)
        if gravity is not None:
            self.gravity = gravity
        self._is_setup = False

    # ---- scene
    def set_box(self, lo, hi, periodic=None):
        """The domain: an open box [lo, hi] (a hint for the grid) or, with
        periodic = (px, py, pz) flags, a periodic one."""
        lo, hi = (np.ascontiguousarray(a, dtype=np.float64).reshape(3) for a in (lo, hi))
        per = None if periodic is None else (ctypes.c_int * 3)(*[int(bool(p)) for p in periodic])
        call("tl_api_dem_set_box", self._h, lo.ctypes.data_as(_lib.c_double_p),
             hi.ctypes.data_as(_lib.c_double_p), per)

    @property
    def gravity(self):
        """Gravity (m/s^2) on every free particle; a copy: assign to change it."""
        return self._gravity.copy()

    @gravity.setter
    def gravity(self, g):
        self._gravity = np.asarray(g, dtype=float).reshape(3).copy()
        lib.tl_dem_set_gravity(self._h, _vec3(self._gravity))

    def add_species(self, name, density, r_min, r_max=None):
        """A material (kg/m^3) and radii drawn uniformly in diameter in
        [r_min, r_max] (m); returns its index."""
        k = ctypes.c_int()
        call("tl_particles_add_species", self._p, cstr(name), float(density), float(r_min),
             float(r_min if r_max is None else r_max), ctypes.byref(k))
        return k.value

    def add_law(self, law):
        """Gives a ContactLaw to the world (which then owns it); returns its index."""
        _check_owned(law)
        k = ctypes.c_int()
        call("tl_dem_add_law", self._h, law._h, ctypes.byref(k))
        law._owner = self
        return k.value

    def set_pair_law(self, species_a, species_b, law):
        call("tl_dem_set_pair_law", self._h, int(species_a), int(species_b), int(law))

    def add_wall(self, wall, law=0):
        """Gives a Wall to the world (which then owns it); its contacts use law `law`."""
        _check_owned(wall)
        call("tl_dem_add_wall", self._h, wall._h, int(law))
        wall._owner = self
        return wall

    @property
    def n_walls(self):
        return lib.tl_dem_n_walls(self._h)

    def wall(self, k):
        """Wall k of the world in the order added (a coupling's wall too), as a Wall handle."""
        if not 0 <= k < self.n_walls:
            raise IndexError(f"wall {k} of a world of {self.n_walls} walls")
        w = Wall.__new__(Wall)
        w._h = ctypes.c_void_p(lib.tl_dem_wall(self._h, int(k)))
        w._owner = self
        w.type = lib.tl_api_wall_type(w._h).decode()
        return w

    def reserve(self, n):
        """Room for n particles: insertions up to n do not reallocate (views stay valid)."""
        call("tl_particles_reserve", self._p, int(n))

    def add_particle(self, x, v=(0, 0, 0), radius=None, species=0):
        """Inserts a free particle (before or after setup); returns its current index."""
        if radius is None:
            raise ValueError("add_particle needs a radius (m)")
        i = ctypes.c_size_t()
        call("tl_dem_add_particle", self._h, _vec3(x), _vec3(v), float(radius), int(species), ctypes.byref(i))
        return i.value

    def add_particles(self, x, radius, v=None, species=0):
        """Inserts n particles: x (n, 3), radius (n,) or one value, v (n, 3)
        or None; returns their ids."""
        x = np.asarray(x, dtype=float).reshape(-1, 3)
        r = np.broadcast_to(np.asarray(radius, dtype=float), (x.shape[0],))
        v = np.zeros_like(x) if v is None else np.asarray(v, dtype=float).reshape(-1, 3)
        self.reserve(self.n + x.shape[0])
        idx = [self.add_particle(x[k], v[k], r[k], species) for k in range(x.shape[0])]
        return self.id[idx].copy()

    def add_particles_from_file(self, path, species=-1):
        """Adds the particles of a LAMMPS data file (atom_style sphere or
        granular) or of a Talus HDF5 particle snapshot (told by the file's
        first bytes): positions, radii, velocities.  species >= 0 gives every
        particle that species; -1 takes it from the file (LAMMPS type t is
        species t - 1), each must exist in the world.  Masses follow from
        the species' density; the world numbers the particles itself.
        Returns how many were added."""
        n = ctypes.c_size_t()
        call("tl_dem_add_particles_from_file", self._h, cstr(path), int(species), ctypes.byref(n))
        return n.value

    def add_bond(self, id_a, id_b):
        """A bond between the particles of ids id_a and id_b (for a bonded law)."""
        call("tl_dem_add_bond", self._h, int(id_a), int(id_b))

    def remove_particle(self, index):
        """Removes particle `index`; the last particle moves into its slot."""
        call("tl_dem_remove_particle", self._h, int(index))

    def set_motion(self, index, motion):
        """'free', 'fixed' or 'prescribed' (TL_MOTION_*)."""
        call("tl_particles_set_motion", self._p, int(index), MOTION[motion] if isinstance(motion, str) else motion)

    def enable_rotation(self):
        """Allocates the rotational state (q, w, torque, inv_inertia) now;
        set-up does it anyway when a law needs rotation."""
        call("tl_particles_enable_rotation", self._p)

    def enable_external_force(self):
        """Allocates f_ext, a per-particle force added to each step's (N)."""
        call("tl_particles_enable_external_force", self._p)

    def find(self, particle_id):
        """The current index of the particle with this id."""
        i = ctypes.c_size_t()
        call("tl_particles_find", self._p, int(particle_id), ctypes.byref(i))
        return i.value

    # ---- particle views (see the module's note on their validity)
    def field(self, name):
        """A numpy view of particle field `name` (x, v, f, radius, mass,
        inv_mass, species, motion, id, q, w, torque, inv_inertia, f_ext,
        f_coupling, weight): shape (n, 3) for vectors, (n, 4) for q, (n,)
        for scalars.  No copy: writing to it writes the world's arrays."""
        data, n = ctypes.c_void_p(), ctypes.c_size_t()
        comp, scalar = ctypes.c_int(), ctypes.c_int()
        call("tl_api_particles_field", self._p, cstr(name), ctypes.byref(data), ctypes.byref(n),
             ctypes.byref(comp), ctypes.byref(scalar))
        return view(address(data), n.value, comp.value, scalar.value, self)

    x = property(lambda self: self.field("x"), doc="positions (n, 3), m")
    v = property(lambda self: self.field("v"), doc="velocities (n, 3), m/s")
    f = property(lambda self: self.field("f"),
                 doc="forces of the last evaluation (n, 3), N: contacts, walls and gravity m g included")
    radius = property(lambda self: self.field("radius"), doc="radii (n,), m")
    mass = property(lambda self: self.field("mass"), doc="masses (n,), kg")
    id = property(lambda self: self.field("id"), doc="stable ids (n,), int64")
    species = property(lambda self: self.field("species"), doc="species indices (n,)")
    w = property(lambda self: self.field("w"), doc="angular velocities (n, 3), rad/s (rotation enabled)")
    torque = property(lambda self: self.field("torque"), doc="torques (n, 3), N m (rotation enabled)")

    @property
    def n(self):
        n, cap = ctypes.c_size_t(), ctypes.c_size_t()
        lib.tl_api_particles_size(self._p, ctypes.byref(n), ctypes.byref(cap))
        return n.value

    @property
    def capacity(self):
        n, cap = ctypes.c_size_t(), ctypes.c_size_t()
        lib.tl_api_particles_size(self._p, ctypes.byref(n), ctypes.byref(cap))
        return cap.value

    # ---- time stepping
    @property
    def sort_interval(self):
        return self._sort_interval

    @sort_interval.setter
    def sort_interval(self, rebuilds):
        """Renumber particles in grid order every `rebuilds` neighbour-list
        rebuilds (library default 10); 0 never (indices then change only by
        insertion and removal)."""
        self._sort_interval = int(rebuilds)
        lib.tl_dem_set_sort_interval(self._h, self._sort_interval)

    _sort_interval = 10

    def set_threads(self, n):
        lib.tl_dem_set_threads(self._h, int(n))

    def set_skin(self, fraction_of_diameter):
        call("tl_dem_set_skin", self._h, float(fraction_of_diameter))

    def critical_timestep(self):
        """The Velocity-Verlet stability estimate dt_c (s) of the scene as it stands."""
        dt, k, m = ctypes.c_double(), ctypes.c_double(), ctypes.c_double()
        call("tl_dem_critical_timestep", self._h, ctypes.byref(dt), ctypes.byref(k), ctypes.byref(m))
        return dt.value

    @property
    def timestep(self):
        return lib.tl_dem_timestep(self._h)

    @timestep.setter
    def timestep(self, dt):
        call("tl_dem_set_timestep", self._h, float(dt), 0)

    def set_timestep(self, dt, allow_above_critical=False):
        call("tl_dem_set_timestep", self._h, float(dt), int(bool(allow_above_critical)))

    @property
    def time(self):
        return lib.tl_dem_time(self._h)

    def track_energy(self, on=True):
        """Book work and dissipation (needed for a meaningful energy()['total'])."""
        lib.tl_dem_track_energy(self._h, int(bool(on)))

    def setup(self):
        call("tl_dem_setup", self._h)
        self._is_setup = True

    def step(self, n=1):
        """n Velocity-Verlet steps (set up first).  Views taken before may be stale (renumbering)."""
        call("tl_dem_step", self._h, int(n))

    def compute_forces(self):
        """Forces at the current state without moving (after editing positions)."""
        call("tl_dem_compute_forces", self._h)

    # ---- diagnostics
    def energy(self):
        """Energies (J) and momenta of the current state, as a dict."""
        e = _lib.DemEnergy()
        call("tl_dem_energy", self._h, ctypes.byref(e))
        d = {name: getattr(e, name) for name, _ in _lib.DemEnergy._fields_[:7]}
        d["momentum"] = np.array([e.momentum.x, e.momentum.y, e.momentum.z])
        d["angular_momentum"] = np.array([e.angular_momentum.x, e.angular_momentum.y, e.angular_momentum.z])
        return d

    def coordination(self):
        """Mean contacts per free particle, and the same without rattlers."""
        z, zr = ctypes.c_double(), ctypes.c_double()
        call("tl_dem_coordination", self._h, ctypes.byref(z), ctypes.byref(zr))
        return z.value, zr.value

    def contacts(self):
        """The touching particle-particle contacts of the last force
        evaluation, as arrays (copies): i, j (current indices), force on i
        (N), branch vector from i to j and contact point (m), each (n, 3)."""
        n = ctypes.c_size_t()
        call("tl_api_dem_contacts", self._h, 0, ctypes.byref(n), None, None, None, None, None)
        i, j = np.zeros(n.value, dtype=np.int64), np.zeros(n.value, dtype=np.int64)
        f, b, p = (np.zeros((n.value, 3)) for _ in range(3))
        call("tl_api_dem_contacts", self._h, n.value, ctypes.byref(n), *(a.ctypes.data for a in (i, j, f, b, p)))
        return {"i": i, "j": j, "force": f, "branch": b, "point": p}

    def stats(self):
        s = _lib.DemStats()
        lib.tl_dem_stats(self._h, ctypes.byref(s))
        return {name: getattr(s, name) for name, _ in _lib.DemStats._fields_}
