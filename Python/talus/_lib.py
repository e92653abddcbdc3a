"""The shared library, its function prototypes and the error check.

The library is found, in this order, through the environment variable
TALUS_LIBRARY (a path to libtalus.so), the file _paths.py that the build
writes beside the package (the build tree's library, or the installed one
after `make install`), and the system's search path (ctypes.util).
"""
import ctypes
import ctypes.util
import os

c_double_p = ctypes.POINTER(ctypes.c_double)
c_int_p = ctypes.POINTER(ctypes.c_int)
c_size_p = ctypes.POINTER(ctypes.c_size_t)
c_char_pp = ctypes.POINTER(ctypes.c_char_p)
handle = ctypes.c_void_p
handle_p = ctypes.POINTER(ctypes.c_void_p)


class Vec3(ctypes.Structure):
    _fields_ = [("x", ctypes.c_double), ("y", ctypes.c_double), ("z", ctypes.c_double)]


class DemEnergy(ctypes.Structure):
    _fields_ = [(n, ctypes.c_double) for n in ("kinetic_translational", "kinetic_rotational", "elastic",
                                                "gravitational", "work_external", "dissipated", "total")] + \
               [("momentum", Vec3), ("angular_momentum", Vec3)]


class DemStats(ctypes.Structure):
    _fields_ = [("steps", ctypes.c_long), ("rebuilds", ctypes.c_long),
                ("n_contacts", ctypes.c_size_t), ("n_pairs", ctypes.c_size_t)]


class CoupledEnergy(ctypes.Structure):
    _fields_ = [(n, ctypes.c_double) for n in ("dem_kinetic", "dem_elastic", "dem_gravitational", "fem_kinetic",
                                                "fem_strain", "work_on_solid", "work_on_particles", "total")]


class Energies(ctypes.Structure):
    _fields_ = [(n, ctypes.c_double) for n in ("kinetic", "strain", "external_work", "total")]


class WallSetting(ctypes.Structure):
    _fields_ = [("name", ctypes.c_char_p), ("value", ctypes.c_double)]


class VCouplingZone(ctypes.Structure):
    _fields_ = [("axis", ctypes.c_int), ("lo", ctypes.c_double), ("hi", ctypes.c_double)]


class VCouplingParams(ctypes.Structure):
    _fields_ = [("zone", VCouplingZone), ("c", ctypes.c_double), ("kernel", ctypes.c_char_p),
                ("epsilon", ctypes.c_double), ("quad_order", ctypes.c_int), ("per_element", ctypes.c_int)]


class VCouplingDiag(ctypes.Structure):
    _fields_ = [("n_active", ctypes.c_size_t), ("n_entries", ctypes.c_size_t), ("residual_max", ctypes.c_double),
                ("residual_rms", ctypes.c_double), ("force_fem", ctypes.c_double * 3),
                ("force_dem", ctypes.c_double * 3), ("eq41", ctypes.c_double), ("work_fem", ctypes.c_double),
                ("work_dem", ctypes.c_double)]


class TalusError(RuntimeError):
    """A Talus call failed.  `status` is the library's TlStatus code,
    `status_name` its name ("invalid argument", ...), and `message` the
    library's message: what was refused, the offending value and the limit,
    then the trace of calls ("at file:line")."""

    def __init__(self, status, status_name, message):
        self.status = status
        self.status_name = status_name
        self.message = message
        super().__init__(f"{status_name}: {message}")


def _library_path():
    env = os.environ.get("TALUS_LIBRARY")
    if env:
        return env, "TALUS_LIBRARY"
    try:
        from . import _paths  # written by the build or by the install
        if os.path.exists(_paths.LIBRARY):
            return _paths.LIBRARY, "_paths.py"
    except ImportError:
        pass
    found = ctypes.util.find_library("talus")
    if found:
        return found, "the system's library path"
    raise ImportError("libtalus.so not found: set TALUS_LIBRARY to its path, or use the package from the build "
                      "tree (build/python) or from `make install`")


path, found_through = _library_path()
lib = ctypes.CDLL(path)

# name: (restype, argtypes); a restype of TlStatus is ctypes.c_int checked by call().
S = ctypes.c_int
_prototypes = {
    "tl_initialize": (S, []),
    "tl_error_message": (ctypes.c_char_p, []),
    "tl_error_clear": (None, []),
    "tl_status_name": (ctypes.c_char_p, [ctypes.c_int]),
    "tl_registry_list": (ctypes.c_size_t, [ctypes.c_char_p, c_char_pp, ctypes.c_size_t]),
    "tl_api_sizeof": (ctypes.c_size_t, [ctypes.c_char_p]),
    "tl_api_type_param": (S, [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_int, c_int_p, c_char_pp, c_double_p,
                              c_double_p, c_double_p, c_char_pp, c_char_pp]),
    # DEM world
    "tl_dem_create": (S, [handle_p]),
    "tl_dem_destroy": (None, [handle_p]),
    "tl_dem_particles": (handle, [handle]),
    "tl_api_dem_set_box": (S, [handle, c_double_p, c_double_p, c_int_p]),
    "tl_dem_set_gravity": (None, [handle, Vec3]),
    "tl_dem_set_skin": (S, [handle, ctypes.c_double]),
    "tl_dem_set_threads": (None, [handle, ctypes.c_int]),
    "tl_dem_set_sort_interval": (None, [handle, ctypes.c_int]),
    "tl_dem_set_dimension": (S, [handle, ctypes.c_int]),
    "tl_dem_add_law": (S, [handle, handle, c_int_p]),
    "tl_dem_set_pair_law": (S, [handle, ctypes.c_int, ctypes.c_int, ctypes.c_int]),
    "tl_dem_add_wall": (S, [handle, handle, ctypes.c_int]),
    "tl_dem_n_walls": (ctypes.c_size_t, [handle]),
    "tl_dem_set_timestep": (S, [handle, ctypes.c_double, ctypes.c_int]),
    "tl_dem_timestep": (ctypes.c_double, [handle]),
    "tl_dem_time": (ctypes.c_double, [handle]),
    "tl_dem_critical_timestep": (S, [handle, c_double_p, c_double_p, c_double_p]),
    "tl_dem_setup": (S, [handle]),
    "tl_dem_step": (S, [handle, ctypes.c_long]),
    "tl_dem_compute_forces": (S, [handle]),
    "tl_dem_add_particle": (S, [handle, Vec3, Vec3, ctypes.c_double, ctypes.c_int, c_size_p]),
    "tl_dem_remove_particle": (S, [handle, ctypes.c_size_t]),
    "tl_dem_track_energy": (None, [handle, ctypes.c_int]),
    "tl_dem_energy": (S, [handle, ctypes.POINTER(DemEnergy)]),
    "tl_dem_coordination": (S, [handle, c_double_p, c_double_p]),
    "tl_dem_stats": (None, [handle, ctypes.POINTER(DemStats)]),
    "tl_api_dem_contacts": (S, [handle, ctypes.c_size_t, c_size_p] + [handle] * 5),
    "tl_dem_add_bond": (S, [handle, ctypes.c_int64, ctypes.c_int64]),
    "tl_dem_add_particles_from_file": (S, [handle, ctypes.c_char_p, ctypes.c_int, c_size_p]),
    # particles
    "tl_particles_add_species": (S, [handle, ctypes.c_char_p, ctypes.c_double, ctypes.c_double, ctypes.c_double,
                                     c_int_p]),
    "tl_particles_set_motion": (S, [handle, ctypes.c_size_t, ctypes.c_int]),
    "tl_particles_enable_rotation": (S, [handle]),
    "tl_particles_enable_external_force": (S, [handle]),
    "tl_particles_reserve": (S, [handle, ctypes.c_size_t]),
    "tl_particles_find": (S, [handle, ctypes.c_int64, c_size_p]),
    "tl_api_particles_field": (S, [handle, ctypes.c_char_p, handle_p, c_size_p, c_int_p, c_int_p]),
    "tl_api_particles_size": (None, [handle, c_size_p, c_size_p]),
    # contact laws
    "tl_contact_law_create": (S, [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_char_p, ctypes.c_char_p, handle_p]),
    "tl_contact_law_set": (S, [handle, ctypes.c_char_p, ctypes.c_double]),
    "tl_contact_law_get": (S, [handle, ctypes.c_char_p, c_double_p]),
    "tl_contact_law_setup": (S, [handle]),
    "tl_contact_law_destroy": (None, [handle_p]),
    # walls
    "tl_wall_create": (S, [ctypes.c_char_p, ctypes.c_size_t, ctypes.POINTER(WallSetting), handle_p]),
    "tl_wall_destroy": (None, [handle_p]),
    "tl_dem_wall": (handle, [handle, ctypes.c_size_t]),
    "tl_api_wall_type": (ctypes.c_char_p, [handle]),
    "tl_api_wall_account": (None, [handle, c_double_p, c_double_p, c_size_p, c_double_p, c_double_p]),
    "tl_trisurface_create": (S, [ctypes.c_size_t, c_double_p, ctypes.c_size_t, c_int_p, handle_p]),
    "tl_trisurface_create_rectangle": (S, [ctypes.c_double] * 5 + [ctypes.c_int] * 3 + [handle_p]),
    "tl_trisurface_destroy": (None, [handle_p]),
    "tl_trisurface_set_vertices": (S, [handle, c_double_p, c_double_p]),
    "tl_wall_trisurface_set_surface": (S, [handle, handle]),
    "tl_wall_trisurface_set_corrections": (S, [handle, ctypes.c_int]),
    "tl_wall_trisurface_set_brute_force": (S, [handle, ctypes.c_int]),
    "tl_wall_trisurface_set_drift": (S, [handle, ctypes.c_int]),
    "tl_wall_trisurface_set_feature_angle": (S, [handle, ctypes.c_double]),
    "tl_wall_trisurface_surface": (handle, [handle]),
    "tl_api_trisurface_arrays": (None, [handle, handle_p, handle_p, c_size_p, handle_p, c_size_p]),
    "tl_api_wall_from_file": (S, [ctypes.c_char_p, ctypes.c_double, c_double_p, c_double_p, ctypes.c_int,
                                  ctypes.c_int, handle_p, c_double_p]),
    # meshes, materials, solids, steppers
    "tl_element_type_find": (S, [ctypes.c_char_p, handle_p]),
    "tl_mesh_create_box": (S, [handle, c_size_p, c_double_p, c_double_p, handle_p]),
    "tl_mesh_read_gmsh": (S, [ctypes.c_char_p, handle_p]),
    "tl_mesh_destroy": (None, [handle_p]),
    "tl_mesh_volume": (ctypes.c_double, [handle]),
    "tl_api_mesh_nodes": (None, [handle, c_int_p, c_size_p, handle_p]),
    "tl_api_mesh_node_set": (S, [handle, ctypes.c_char_p, c_size_p, handle_p]),
    "tl_material_create": (S, [ctypes.c_char_p, handle_p]),
    "tl_material_set": (S, [handle, ctypes.c_char_p, ctypes.c_double]),
    "tl_material_get": (S, [handle, ctypes.c_char_p, c_double_p]),
    "tl_material_setup": (S, [handle]),
    "tl_material_destroy": (None, [handle_p]),
    "tl_solid_create": (S, [handle, handle_p]),
    "tl_solid_destroy": (None, [handle_p]),
    "tl_solid_set_material": (S, [handle, ctypes.c_char_p, handle]),
    "tl_solid_fix": (S, [handle, ctypes.c_char_p, ctypes.c_int]),
    "tl_solid_add_gravity": (S, [handle, Vec3]),
    "tl_solid_setup": (S, [handle]),
    "tl_solid_system": (handle, [handle]),
    "tl_solid_total_mass": (ctypes.c_double, [handle]),
    "tl_solid_dofs_to_nodes": (None, [handle, c_double_p, c_double_p]),
    "tl_solid_reactions": (S, [handle, ctypes.c_double, c_double_p, c_double_p, c_double_p]),
    "tl_api_stepper_create": (S, [ctypes.c_char_p, handle, ctypes.c_char_p, ctypes.c_size_t, c_char_pp, c_double_p,
                                  handle_p]),
    "tl_api_stepper_state": (None, [handle, c_double_p, c_size_p, handle_p, handle_p, handle_p]),
    "tl_stepper_set_state": (S, [handle, ctypes.c_double, c_double_p, c_double_p]),
    "tl_stepper_step": (S, [handle, ctypes.c_double]),
    "tl_stepper_energies": (S, [handle, ctypes.POINTER(Energies)]),
    "tl_stepper_critical_dt": (S, [handle, c_double_p]),
    "tl_stepper_destroy": (None, [handle_p]),
    # surface coupling
    "tl_api_scoupling_create_boundary": (S, [handle, ctypes.c_int, c_char_pp, ctypes.c_char_p, ctypes.c_size_t,
                                             c_char_pp, c_double_p, handle_p]),
    "tl_scoupling_destroy": (None, [handle_p]),
    "tl_scoupling_add_to_dem": (S, [handle, handle, ctypes.c_int]),
    "tl_scoupling_wall": (handle, [handle]),
    "tl_scoupling_n_contacts": (ctypes.c_size_t, [handle]),
    "tl_scoupling_n_elements": (ctypes.c_size_t, [handle]),
    "tl_scoupling_n_active_elements": (ctypes.c_size_t, [handle]),
    "tl_api_coupled_loop_create": (S, [handle, handle, handle, ctypes.c_int, handle_p, ctypes.c_size_t, c_char_pp,
                                       c_double_p, handle_p]),
    "tl_coupled_loop_destroy": (None, [handle_p]),
    "tl_coupled_loop_step": (S, [handle]),
    "tl_coupled_loop_energy": (S, [handle, ctypes.POINTER(CoupledEnergy)]),
    "tl_coupled_loop_time": (ctypes.c_double, [handle]),
    "tl_api_coupled_loop_arrays": (None, [handle, handle_p, handle_p, handle_p]),
    "tl_api_coupled_loop_wall_force": (None, [handle, c_double_p]),
    # volume coupling
    "tl_api_vcoupled_create": (S, [handle, handle, ctypes.POINTER(VCouplingParams), ctypes.c_char_p, handle_p]),
    "tl_api_vcoupled_stepper": (handle, [handle]),
    "tl_api_vcoupled_u_nodes": (c_double_p, [handle]),
    "tl_api_vcoupled_diag": (None, [handle, ctypes.POINTER(VCouplingDiag), c_double_p]),
    "tl_api_vcoupled_destroy": (None, [handle_p]),
}
for _name, (_res, _args) in _prototypes.items():
    _f = getattr(lib, _name)
    _f.restype = _res
    _f.argtypes = _args


def error_message():
    return lib.tl_error_message().decode("utf-8", "replace")


def call(name, *args):
    """Calls the TlStatus function `name`; a failure raises TalusError with
    the library's message."""
    lib.tl_error_clear()
    status = getattr(lib, name)(*args)
    if status != 0:
        raise TalusError(status, lib.tl_status_name(status).decode(), error_message())


def cstr(s):
    return None if s is None else str(s).encode()


def named_settings(settings):
    """(n, names, values) C arrays of a dict of numeric settings."""
    n = len(settings)
    names = (ctypes.c_char_p * max(n, 1))(*[cstr(k) for k in settings])
    values = (ctypes.c_double * max(n, 1))(*[float(v) for v in settings.values()])
    return n, names, values


# The plain-data structs mirrored above must match the library's.
for _cls, _cname in ((Vec3, "TlVec3"), (DemEnergy, "TlDemEnergy"), (DemStats, "TlDemStats"),
                     (CoupledEnergy, "TlCoupledEnergy"), (Energies, "TlEnergies"), (WallSetting, "TlWallSetting"),
                     (VCouplingDiag, "TlVCouplingDiag"), (VCouplingParams, "TlVCouplingParams")):
    _size = lib.tl_api_sizeof(_cname.encode())
    if _size != ctypes.sizeof(_cls):
        raise ImportError(f"{path}: {_cname} is {_size} bytes in the library, {ctypes.sizeof(_cls)} in the "
                          "Python package: package and library are from different versions")

call("tl_initialize")


# ---- object life cycles
# A Python object holds one library handle and frees it with the type's
# destroy function.  What a handle borrows (a solid its mesh, a coupling its
# solid, a loop its world, solid, stepper and couplings) must outlive it:
# the borrower holds the borrowed objects, so reference counting frees
# borrowers first.  The cycle collector (a traceback kept in a frame, an
# object graph the user made cyclic) finalizes in any order, so an object
# still borrowed when finalized only marks itself and is freed by the last
# borrower's release.  At interpreter exit nothing is freed: the process's
# memory goes with it, and the library's destroy functions are not called
# on a half-torn-down interpreter.
import atexit

_exiting = False


def _at_exit():
    global _exiting
    _exiting = True


atexit.register(_at_exit)


class Handle:
    _h = None
    _owner = None       # the world that took ownership (laws, walls), or None
    _destroy_name = None
    _borrowers = 0
    _dying = False
    _borrowed = ()

    def _init_handle(self, destroy_name, borrowed=()):
        self._h = ctypes.c_void_p()
        self._destroy_name = destroy_name
        self._borrowed = list(borrowed)
        for o in self._borrowed:
            o._borrowers += 1

    def _free(self):
        h, self._h = self._h, None
        if h and self._owner is None and not _exiting:
            getattr(lib, self._destroy_name)(ctypes.byref(h))
        borrowed, self._borrowed = self._borrowed, ()
        for o in borrowed:
            o._borrowers -= 1
            if o._dying and o._borrowers == 0:
                o._free()

    def __del__(self):
        if self._borrowers > 0:
            self._dying = True
        else:
            self._free()
