"""numpy arrays as the C API's vec3 inputs and outputs, without copies
where the array's layout allows."""

from __future__ import annotations

import ctypes
import operator
from typing import Optional

import numpy as np

from . import _native

FLOAT32, FLOAT64 = 0, 1


def _scalar_type(dtype: np.dtype) -> int:
    if dtype == np.float32:
        return FLOAT32
    if dtype == np.float64:
        return FLOAT64
    raise TypeError(f"expected float32 or float64 components, found {dtype}")


def _rows(array: np.ndarray, name: str) -> np.ndarray:
    if array.ndim != 2 or array.shape[1] != 3:
        raise ValueError(f"{name}: expected an (n, 3) array, found shape {array.shape}")
    # Rows may be strided (a view of a wider array), components must be packed.
    if array.strides[1] != array.itemsize or array.strides[0] < 3 * array.itemsize:
        array = np.ascontiguousarray(array)
    return array


def vec3_input(array, name: str = "positions") -> tuple:
    """(dfm_vec3_input, the array it points at): float32/float64 (n, 3)
    read in place; other float types are converted."""
    a = np.asarray(array)
    if a.dtype not in (np.float32, np.float64):
        a = a.astype(np.float64)
    a = _rows(a, name)
    v = _native.Vec3Input(a.ctypes.data, a.shape[0], a.strides[0], _scalar_type(a.dtype))
    return v, a


def new_vec3(count: int, dtype, out: Optional[np.ndarray], name: str = "out") -> np.ndarray:
    """``out`` checked as a writable (count, 3) float array, or a new one."""
    if out is None:
        return np.empty((count, 3), dtype=dtype)
    if out.ndim != 2 or out.shape[1] != 3 or out.shape[0] < count:
        raise ValueError(f"{name}: expected a ({count}, 3) array, found shape {out.shape}")
    _scalar_type(out.dtype)
    if not out.flags.writeable or out.strides[1] != out.itemsize:
        raise ValueError(f"{name}: must be writable with packed x, y, z")
    return out


def vec3_output(array: np.ndarray) -> _native.Vec3Output:
    return _native.Vec3Output(array.ctypes.data, array.shape[0], array.strides[0],
                              _scalar_type(array.dtype))


def index_array(values, name: str, columns: Optional[int] = None) -> np.ndarray:
    """Vertex indices as packed uint32 (copied only when they are not)."""
    a = np.asarray(values)
    if a.dtype != np.uint32:
        if a.size and not np.issubdtype(a.dtype, np.integer):
            raise TypeError(f"{name}: expected integer vertex indices, found {a.dtype}")
        if a.size and (a.min() < 0 or a.max() > 0xFFFFFFFF):
            raise ValueError(f"{name}: vertex indices must lie in 0 .. 2**32 - 1")
        a = a.astype(np.uint32)
    if columns is not None and (a.ndim != 2 or a.shape[1] != columns):
        raise ValueError(f"{name}: expected an (m, {columns}) array, found shape {a.shape}")
    if columns is None:
        a = a.reshape(-1)
    return np.ascontiguousarray(a)


def uint32_pointer(array: np.ndarray):
    return array.ctypes.data_as(ctypes.POINTER(ctypes.c_uint32))


#: The largest vertex index: 2**32 - 1 is the library's "no vertex".
MAX_VERTEX = 0xFFFFFFFE


def unsigned(value, name: str, limit: int = 0xFFFFFFFFFFFFFFFF, what: str = "an integer") -> int:
    """An integer argument of an unsigned C parameter, checked here: ctypes
    would turn -1 into 2**32 - 1."""
    v = operator.index(value)
    if not 0 <= v <= limit:
        raise ValueError(f"{name}: expected {what} from 0 to {limit}, found {v}")
    return v


def vertex_index(value, name: str) -> int:
    """A vertex index argument (0 to 2**32 - 2)."""
    return unsigned(value, name, MAX_VERTEX, "a vertex index, an integer")
