"""The surface coupling of a DEM world and a solid (tl_scoupling.h), the
coupled time loop (tl_coupled_loop.h) and the volume-coupled loop
(tl_api_vcoupled_*, tl_vcoupling.h).

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


class VolumeCoupledLoop(_lib.Handle):
    """A world's particles and a solid coupled through their volume
    (TlVCoupling: Arlequin weights over the zone, a penalty tying the
    particles' homogenised displacement to the elements'), stepped in
    lock-step: after creation every world.step(n) also steps the solid by
    the world's dt and applies the coupling forces to both.

    Create it after the particles are in the world and before
    world.setup(), over a Solid made with setup=False (material and
    supports given): it sets the solid up and makes its own stepper
    (`stepper`, default central_difference, at rest at t = 0).
    zone = (axis, lo, hi): particle weight 1 below lo, 0 above hi along the
    axis (0 x, 1 y, 2 z), in m; width: CG width c in m (0: the classical
    Eq. 19); kernel: a CG kernel for c > 0; penalty in Pa/m^2."""

    def __init__(self, world, solid, zone, penalty, width=0.0, kernel="lucy", quad_order=4, per_element=False,
                 stepper="central_difference"):
        self.world, self.solid = world, solid
        self._init_handle("tl_api_vcoupled_destroy", borrowed=(world, solid))
        self._kernel = cstr(kernel)  # the library keeps the name
        p = _lib.VCouplingParams(_lib.VCouplingZone(int(zone[0]), float(zone[1]), float(zone[2])), float(width),
                                 self._kernel, float(penalty), int(quad_order), int(bool(per_element)))
        call("tl_api_vcoupled_create", world._h, solid._h, ctypes.byref(p), cstr(stepper), ctypes.byref(self._h))
        from .fem import Stepper
        st = Stepper.__new__(Stepper)  # the loop's own stepper, borrowed: freed with the loop
        st.solid = solid
        st._h = ctypes.c_void_p(lib.tl_api_vcoupled_stepper(self._h))
        st._owner = self
        self.stepper = st

    @property
    def u(self):
        """Node displacements (n_nodes, 3) at the world's time: a read-only view of the loop's array."""
        a = lib.tl_api_vcoupled_u_nodes(self._h)
        return view(ctypes.cast(a, ctypes.c_void_p).value, self.solid.mesh.n_nodes, 3, 0, self, readonly=True)

    def diag(self):
        """The last step's coupling account: force_fem and force_dem (the
        sums of the nodal and of the particle coupling forces, N), eq41
        (|force_fem + force_dem| over the sum of |nodal forces|), the
        largest eq41 so far, work_fem and work_dem (J), the coupled nodes
        and Pi's entries."""
        d, worst = _lib.VCouplingDiag(), ctypes.c_double()
        lib.tl_api_vcoupled_diag(self._h, ctypes.byref(d), ctypes.byref(worst))
        return {"force_fem": np.array(d.force_fem[:]), "force_dem": np.array(d.force_dem[:]), "eq41": d.eq41,
                "eq41_max": worst.value, "work_fem": d.work_fem, "work_dem": d.work_dem, "n_active": d.n_active,
                "n_entries": d.n_entries, "residual_max": d.residual_max}
