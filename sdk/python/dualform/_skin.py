"""numpy arrays as a skin's C inputs (dfm_skin_input) and joint matrices:
joints and weights read in place where their layout allows, 4x4 matrices
in the math convention (M @ p) turned into the C API's column-major."""

from __future__ import annotations

import ctypes
from typing import Optional, Tuple

import numpy as np

from . import _arrays, _native

# dfm_index_type by numpy dtype.
_INDEX_TYPES = {np.dtype(np.uint32): 0, np.dtype(np.uint16): 1, np.dtype(np.uint8): 2}


def _packed_rows(array: np.ndarray) -> np.ndarray:
    """Rows may be strided (a view of a wider array); a row's entries must
    be packed."""
    if array.shape[1] and (array.strides[1] != array.itemsize
                           or array.strides[0] < array.shape[1] * array.itemsize):
        return np.ascontiguousarray(array)
    return array


def joint_indices(values, vertex_count: int) -> np.ndarray:
    """(V, K) joint indices: uint8, uint16 or uint32 read in place; other
    integer types converted after a range check."""
    a = np.asarray(values)
    if a.ndim != 2 or a.shape[0] != vertex_count:
        raise ValueError(f"joints: expected a ({vertex_count}, K) array, one row per vertex, "
                         f"found shape {a.shape}")
    if a.dtype not in _INDEX_TYPES:
        if a.size and not np.issubdtype(a.dtype, np.integer):
            raise TypeError(f"joints: expected integer joint indices, found {a.dtype}")
        if a.size and (a.min() < 0 or a.max() > 0xFFFFFFFF):
            raise ValueError("joints: joint indices must lie in 0 .. 2**32 - 1")
        a = a.astype(np.uint32)
    return _packed_rows(a)


def joint_weights(values, shape: Tuple[int, int]) -> np.ndarray:
    """(V, K) weights: float32 or float64 read in place; other numbers
    converted to float64."""
    a = np.asarray(values)
    if a.shape != shape:
        raise ValueError(f"weights: expected the joints' shape {shape}, found {a.shape}")
    if a.dtype not in (np.float32, np.float64):
        if a.size and not (np.issubdtype(a.dtype, np.floating)
                           or np.issubdtype(a.dtype, np.integer)):
            raise TypeError(f"weights: expected numbers, found {a.dtype}")
        a = a.astype(np.float64)
    return _packed_rows(a)


def column_major(matrices, name: str) -> np.ndarray:
    """(J, 4, 4) matrices acting on column vectors (M @ [x, y, z, 1]) as the
    C API's 16 doubles per matrix, column after column."""
    m = np.asarray(matrices, dtype=np.float64)
    if m.ndim != 3 or m.shape[1:] != (4, 4):
        raise ValueError(f"{name}: expected a (J, 4, 4) array, found shape {m.shape}")
    return np.ascontiguousarray(m.transpose(0, 2, 1))


def from_column_major(values: np.ndarray) -> np.ndarray:
    """16 doubles per matrix, column-major, as (J, 4, 4) matrices M @ p."""
    return np.ascontiguousarray(values.reshape(-1, 4, 4).transpose(0, 2, 1))


def double_pointer(array: Optional[np.ndarray]):
    if array is None:
        return None
    return array.ctypes.data_as(ctypes.POINTER(ctypes.c_double))


def skin_input(vertex_count: int, joints, weights, inverse_bind_matrices) -> tuple:
    """(dfm_skin_input, the arrays it points at, to keep alive during the
    call)."""
    given = [x is not None for x in (joints, weights, inverse_bind_matrices)]
    if not any(given):
        return _native.SkinInput(), ()
    if not all(given):
        raise ValueError("a skin needs joints, weights and inverse_bind_matrices together")
    j = joint_indices(joints, vertex_count)
    w = joint_weights(weights, j.shape)
    ibm = column_major(inverse_bind_matrices, "inverse_bind_matrices")
    if ibm.shape[0] == 0:
        raise ValueError("inverse_bind_matrices: expected one matrix per joint, found none")
    joint_count = _arrays.unsigned(ibm.shape[0], "inverse_bind_matrices' joint count",
                                   0xFFFFFFFF)
    skin = _native.SkinInput()
    skin.joint_count = joint_count
    skin.inverse_bind_matrices = double_pointer(ibm)
    skin.influence_count = _arrays.unsigned(j.shape[1], "joints' influences per vertex",
                                            0xFFFFFFFF)
    skin.joints = j.ctypes.data
    skin.joint_stride = j.strides[0]
    skin.joint_type = _INDEX_TYPES[j.dtype]
    skin.weights = w.ctypes.data
    skin.weight_stride = w.strides[0]
    skin.weight_type = _arrays.FLOAT64 if w.dtype == np.float64 else _arrays.FLOAT32
    return skin, (j, w, ibm)
