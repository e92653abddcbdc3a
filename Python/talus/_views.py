"""numpy arrays over the library's own memory (no copy)."""
import ctypes

import numpy as np

_ctypes_of = {0: ctypes.c_double, 1: ctypes.c_int64, 2: ctypes.c_int32, 3: ctypes.c_uint8}
_numpy_of = {0: np.float64, 1: np.int64, 2: np.int32, 3: np.uint8}


def view(address, n, components, scalar, owner, readonly=False):
    """An (n, components) array (n, for one component) over `address`.
    The array keeps `owner` alive, so the memory is not freed under it while
    the owner lives; what else invalidates it is the owner's to document."""
    shape = (n,) if components == 1 else (n, components)
    if n == 0 or not address:
        a = np.zeros(shape, dtype=_numpy_of[scalar])
    else:
        ctype = _ctypes_of[scalar] * (n * components)
        buf = ctype.from_address(address)
        buf._talus_owner = owner  # the array's base chain holds buf, buf holds the owner
        a = np.ctypeslib.as_array(buf).reshape(shape)
    if readonly:
        a.flags.writeable = False
    return a


def address(p):
    """The integer address held by a c_void_p (0 for NULL)."""
    return p.value or 0
