"""The surface coupling of a DEM world and a solid (tl_scoupling.h) and
the coupled time loop (tl_coupled_loop.h).

    sc = SurfaceCoupling(solid, exclude=["ymin"], width=0.0)
    sc.add_to(world, law=0)          # before world.setup()
    world.setup()
    loop = CoupledLoop(world, solid, stepper, [sc], substeps=10)
    loop.step(100)

CoupledLoop.u, .v and .forces are views (n_nodes, 3) of the loop's own
node-space arrays: valid as long as the loop, updated by every step.
"""
import ctypes

import numpy as np

from . import _lib
from ._lib import call, cstr, lib, named_settings
from ._views import address, view

SCHEMES = {"predict": 0, "interpolate": 1, "parallel": 2, "lagged_walls": 3}
SUPPORTS = {"surface": 0, "elements": 1}


class SurfaceCoupling(_lib.Handle):
    """All boundary faces of the solid's mesh except the named face sets,
    as one coupled boundary: a triangulated DEM wall that follows the
    solid, and the coarse-grained contact tractions (width c in m; 0: the
    point-source limit) the solid receives.  kernel: a registered CG kernel
    (`talus.types("cg_kernel")`); support: "surface" or "elements"."""

    def __init__(self, solid, exclude=(), width=0.0, kernel=None, subdivisions=0, support="surface"):
        self.solid = solid
        self._world = None
        self._init_handle("tl_scoupling_destroy", borrowed=(solid,))
        names = (ctypes.c_char_p * max(len(exclude), 1))(*[cstr(e) for e in exclude])
        settings = {"width": width, "subdivisions": subdivisions,
                    "support": SUPPORTS[support] if isinstance(support, str) else support}
        n, sn, sv = named_settings(settings)
        call("tl_api_scoupling_create_boundary", solid._h, len(exclude), names, cstr(kernel), n, sn, sv,
             ctypes.byref(self._h))

    def add_to(self, world, law=0):
        """Hands the coupling's wall to the world (before world.setup())."""
        call("tl_scoupling_add_to_dem", self._h, world._h, int(law))
        self._world = world

    n_contacts = property(lambda self: lib.tl_scoupling_n_contacts(self._h),
                          doc="wall contacts at the last force evaluation")
    n_elements = property(lambda self: lib.tl_scoupling_n_elements(self._h), doc="SCoupling elements")
    n_active_elements = property(lambda self: lib.tl_scoupling_n_active_elements(self._h))


class CoupledLoop(_lib.Handle):
    """The coupled DEM–FEM loop: each macro step is `substeps` DEM steps of
    the world's dt and one FE step of substeps x dt.  scheme: predict
    (default), interpolate, parallel, lagged_walls; one_way: a rigid solid;
    average_forces: apply the mean of the sub-steps' forces."""

    def __init__(self, world, solid, stepper, couplings, substeps=1, scheme="predict", one_way=False,
                 average_forces=False):
        self.world, self.solid, self.stepper, self.couplings = world, solid, stepper, list(couplings)
        self._init_handle("tl_coupled_loop_destroy", borrowed=(world, solid, stepper, *self.couplings))
        hs = (ctypes.c_void_p * len(self.couplings))(*[c._h.value for c in self.couplings])
        settings = {"substeps": substeps, "scheme": SCHEMES[scheme] if isinstance(scheme, str) else scheme,
                    "one_way": int(bool(one_way)), "average_forces": int(bool(average_forces))}
        n, sn, sv = named_settings(settings)
        call("tl_api_coupled_loop_create", world._h, solid._h, stepper._h, len(self.couplings), hs, n, sn, sv,
             ctypes.byref(self._h))

    def step(self, n=1):
        """n macro steps."""
        for _ in range(int(n)):
            call("tl_coupled_loop_step", self._h)

    @property
    def time(self):
        return lib.tl_coupled_loop_time(self._h)

    def energy(self):
        """Energies (J) of both models and the coupling's work, as a dict
        (total = DEM kinetic + elastic + gravitational + FE kinetic + strain)."""
        e = _lib.CoupledEnergy()
        call("tl_coupled_loop_energy", self._h, ctypes.byref(e))
        return {name: getattr(e, name) for name, _ in _lib.CoupledEnergy._fields_}

    def _arrays(self):
        u, v, f = ctypes.c_void_p(), ctypes.c_void_p(), ctypes.c_void_p()
        lib.tl_api_coupled_loop_arrays(self._h, ctypes.byref(u), ctypes.byref(v), ctypes.byref(f))
        return u, v, f

    u = property(lambda self: view(address(self._arrays()[0]), self.solid.mesh.n_nodes, 3, 0, self, True),
                 doc="node displacements (n_nodes, 3), m: a read-only view")
    v = property(lambda self: view(address(self._arrays()[1]), self.solid.mesh.n_nodes, 3, 0, self, True),
                 doc="node velocities (n_nodes, 3), m/s: a read-only view")
    forces = property(lambda self: view(address(self._arrays()[2]), self.solid.mesh.n_nodes, 3, 0, self, True),
                      doc="coupling forces on the nodes (n_nodes, 3) of the last FE step, N: a read-only view")

    @property
    def wall_force(self):
        """The particle–wall force total (on the particles) the coupling forces balance, N."""
        f = (ctypes.c_double * 3)()
        lib.tl_api_coupled_loop_wall_force(self._h, f)
        return np.array(f[:])

    @property
    def positions(self):
        """Current node positions X + u (n_nodes, 3), m (a copy)."""
        return self.solid.mesh.nodes + self.u
