"""Output for ParaView: HDF5 snapshots with an XDMF series.

    pw = ParticleWriter("out", "particles")   # out/particles_*.h5 + out/particles.xmf
    ww = WallWriter("out", "walls")            # out/walls*.h5 + out/walls.xmf
    sw = SolidWriter(solid, "out", "beam")     # out/beam*.h5 + out/beam.xmf
    pw.write(world); ww.write(world); sw.write(stepper)

Open the .xmf files in ParaView (particles: Glyph filter, Sphere, scale by
"radius", factor 2; the solid: Warp By Vector with the displacement).
The layout of every file is in docs/output.md.
"""
import ctypes

from . import _lib
from ._lib import call, cstr, lib

for _name, _res, _args in (
        ("tl_particle_writer_create", _lib.S, [ctypes.c_char_p, ctypes.c_char_p, _lib.handle_p]),
        ("tl_particle_writer_destroy", None, [_lib.handle_p]),
        ("tl_particle_writer_count", ctypes.c_size_t, [_lib.handle]),
        ("tl_api_particle_writer_write_dem", _lib.S, [_lib.handle, _lib.handle, ctypes.c_int64]),
        ("tl_solid_output_create", _lib.S, [_lib.handle, ctypes.c_char_p, ctypes.c_char_p, _lib.handle_p]),
        ("tl_solid_output_write", _lib.S, [_lib.handle, ctypes.c_int64, ctypes.c_double, _lib.handle,
                                           _lib.handle]),
        ("tl_solid_output_destroy", None, [_lib.handle_p]),
        ("tl_wall_writer_create", _lib.S, [ctypes.c_char_p, ctypes.c_char_p, _lib.handle_p]),
        ("tl_wall_writer_write_dem", _lib.S, [_lib.handle, ctypes.c_int64, _lib.handle]),
        ("tl_wall_writer_destroy", None, [_lib.handle_p])):
    getattr(lib, _name).restype = _res
    getattr(lib, _name).argtypes = _args


class ParticleWriter(_lib.Handle):
    """Snapshots of a world's particles: <dir>/<name>_<k>.h5 and <dir>/<name>.xmf."""

    def __init__(self, directory, name="particles"):
        self._init_handle("tl_particle_writer_destroy")
        call("tl_particle_writer_create", cstr(directory), cstr(name), ctypes.byref(self._h))

    def write(self, world, step=-1):
        """One snapshot at the world's time (step -1: the world's step count)."""
        call("tl_api_particle_writer_write_dem", self._h, world._h, int(step))

    @property
    def count(self):
        return lib.tl_particle_writer_count(self._h)


class WallWriter(_lib.Handle):
    """Snapshots of a world's walls as triangles (planes as patches over the
    world's box): <dir>/<name>*.h5 and <dir>/<name>.xmf."""

    def __init__(self, directory, name="walls"):
        self._init_handle("tl_wall_writer_destroy")
        call("tl_wall_writer_create", cstr(directory), cstr(name), ctypes.byref(self._h))
        self._count = 0

    def write(self, world, step=None):
        """One snapshot of every wall of the world at its time."""
        call("tl_wall_writer_write_dem", self._h, self._count if step is None else int(step), world._h)
        self._count += 1

    @property
    def count(self):
        return self._count


class SolidWriter(_lib.Handle):
    """Snapshots of a solid (displacement, velocity, element stresses):
    <dir>/<name>*.h5 and <dir>/<name>.xmf."""

    def __init__(self, solid, directory, name="solid"):
        self._init_handle("tl_solid_output_destroy", borrowed=(solid,))
        call("tl_solid_output_create", solid._h, cstr(directory), cstr(name), ctypes.byref(self._h))
        self._count = 0

    def write(self, stepper, step=None):
        """One snapshot of the stepper's state at its time."""
        t, n, u, v, a = stepper._state()
        call("tl_solid_output_write", self._h, self._count if step is None else int(step), t, u, v)
        self._count += 1

    @property
    def count(self):
        return self._count
