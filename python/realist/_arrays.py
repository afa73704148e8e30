"""Dtype and shape conversion for ``Scene.from_arrays`` (called by the native module): any
array-like of numbers becomes the C-contiguous float64 / int64 arrays the native side checks
(finite values, indices in range)."""

from __future__ import annotations

from typing import Optional, Tuple

import numpy as np

from . import color


def _float_array(name: str, value: object, cols: "tuple[int, ...]") -> np.ndarray:
    """``value`` as a C-contiguous float64 (n, cols) array, or ValueError naming ``name``."""
    try:
        a = np.asarray(value)
    except Exception as e:  # a ragged list, an object numpy cannot read
        raise ValueError(f"{name}: not an array of numbers ({e})") from None
    if a.dtype == np.bool_ or not (
        np.issubdtype(a.dtype, np.floating) or np.issubdtype(a.dtype, np.integer)
    ):
        raise ValueError(f"{name}: expected numbers, got dtype {a.dtype}")
    if a.ndim != 2 or a.shape[1] not in cols:
        want = " or ".join(f"(n, {c})" for c in cols)
        raise ValueError(f"{name}: expected shape {want}, got {a.shape}")
    return np.ascontiguousarray(a, dtype=np.float64)


def prepare(
    vertices: object,
    faces: object,
    normals: Optional[object] = None,
    uvs: Optional[object] = None,
    colors: Optional[object] = None,
) -> Tuple[np.ndarray, np.ndarray, Optional[np.ndarray], Optional[np.ndarray], Optional[np.ndarray]]:
    v = _float_array("vertices", vertices, (3,))
    try:
        f = np.asarray(faces)
    except Exception as e:
        raise ValueError(f"faces: not an array of integers ({e})") from None
    if not np.issubdtype(f.dtype, np.integer) or f.dtype == np.bool_:
        raise ValueError(f"faces: expected integer vertex indices, got dtype {f.dtype}")
    if f.ndim != 2 or f.shape[1] != 3:
        raise ValueError(f"faces: expected shape (m, 3) (triangles), got {f.shape}")
    if f.dtype == np.uint64 and f.size and int(f.max()) > np.iinfo(np.int64).max:
        raise ValueError(f"faces: index {int(f.max())} is out of range")
    f = np.ascontiguousarray(f, dtype=np.int64)
    n = None if normals is None else _float_array("normals", normals, (3,))
    uv = None if uvs is None else _float_array("uvs", uvs, (2,))
    c = None
    if colors is not None:
        raw = np.asarray(colors)
        if raw.dtype == np.uint8:
            # 8-bit colours (trimesh's) are sRGB-encoded: decoded to linear light here.
            if raw.ndim != 2 or raw.shape[1] not in (3, 4):
                raise ValueError(f"colors: expected shape (n, 3) or (n, 4), got {raw.shape}")
            lin = color.srgb_to_linear(raw[:, :3].astype(np.float64) / 255.0)
            alpha = raw[:, 3:4].astype(np.float64) / 255.0 if raw.shape[1] == 4 else None
        else:
            fl = _float_array("colors", raw, (3, 4))
            lin, alpha = fl[:, :3], (fl[:, 3:4] if fl.shape[1] == 4 else None)
        if alpha is None:
            alpha = np.ones((lin.shape[0], 1))
        c = np.ascontiguousarray(np.concatenate([lin, alpha], axis=1), dtype=np.float64)
    return v, f, n, uv, c
