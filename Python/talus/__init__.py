"""Talus from Python: DEM worlds, walls, meshes, solids and the surface
and volume couplings, scenes from files (LAMMPS data and HDF5 snapshots,
STL and Gmsh surfaces, Gmsh meshes) through the C library's handles, with the particle and node
arrays as numpy views of the library's memory (no copy).

    import talus
    w = talus.World(box=([0, 0, 0], [0.1, 0.1, 0.1]), gravity=(0, 0, -9.81))
    ...
    w.x[:, 2] += 1e-3      # moves every particle: w.x is the world's array

Errors raise talus.TalusError with the library's message (the offending
value, the limit, the trace of calls).  The library is the one named by
TALUS_LIBRARY, else the one the build or the install recorded in
_paths.py, else libtalus from the system's library path.
"""
import ctypes

from . import _lib
from ._lib import TalusError
from .coupling import CoupledLoop, SurfaceCoupling, VolumeCoupledLoop
from .dem import ContactLaw, Wall, World
from .fem import Material, Mesh, Solid, Stepper
from .output import ParticleWriter, SolidWriter, WallWriter

library_path = _lib.path

__all__ = ["TalusError", "World", "ContactLaw", "Wall", "Mesh", "Material", "Solid", "Stepper",
           "SurfaceCoupling", "CoupledLoop", "VolumeCoupledLoop", "ParticleWriter", "SolidWriter", "WallWriter", "types", "parameters",
           "library_path"]


def types(kind):
    """The registered type names of a kind: "contact_normal",
    "contact_friction", "contact_rolling", "contact_adhesion", "wall",
    "material", "element", "stepper", "linear_solver", "cg_kernel", ..."""
    n = _lib.lib.tl_registry_list(kind.encode(), None, 0)
    names = (ctypes.c_char_p * max(n, 1))()
    n = _lib.lib.tl_registry_list(kind.encode(), names, n)
    return [names[k].decode() for k in range(n)]


def parameters(kind, name):
    """The parameters of a registered type, as the catalogue lists them:
    a list of dicts {name, default, lo, hi, unit, help} (default NaN: none,
    the caller gives the value; unit "1": dimensionless).  E.g.
    parameters("stepper", "newmark") gives beta, gamma, rtol, ...: the
    keyword options Stepper(solid, "newmark", ...) takes."""
    n = ctypes.c_int()
    _lib.call("tl_api_type_param", kind.encode(), name.encode(), -1, ctypes.byref(n), None, None, None, None, None,
              None)
    out = []
    for k in range(n.value):
        pn, unit, help_ = ctypes.c_char_p(), ctypes.c_char_p(), ctypes.c_char_p()
        d, lo, hi = ctypes.c_double(), ctypes.c_double(), ctypes.c_double()
        _lib.call("tl_api_type_param", kind.encode(), name.encode(), k, None, ctypes.byref(pn), ctypes.byref(d),
                  ctypes.byref(lo), ctypes.byref(hi), ctypes.byref(unit), ctypes.byref(help_))
        out.append({"name": pn.value.decode(), "default": d.value, "lo": lo.value, "hi": hi.value,
                    "unit": unit.value.decode(), "help": help_.value.decode()})
    return out
