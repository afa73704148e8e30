"""realist's colour toolkit over numpy arrays (what ``realist color`` prints, and crates/color).

Colorimetry follows colour-science's conventions: XYZ scaled so that white has Y = 1, L* in
[0, 100], hue in [0, 1) for HSV/HSL and in degrees for LCh, D65 and the CIE 1931 2 degree
observer. sRGB values are encoded (as in files and on screens) unless a name says linear.

Every array function takes any array-like of shape (..., 3) and returns a float64 array of
the same shape; the delta_e functions take two such arrays of L*a*b* colours and return
shape (...).

    >>> from realist import color
    >>> color.convert("#ff8000", to=["lab"])["lab"]  # doctest: +ELLIPSIS
    [67.050..., 42.834..., 74.030...]
    >>> float(color.delta_e_2000(color.srgb_to_lab([1, 0, 0]), color.srgb_to_lab([0.9, 0, 0])))  # doctest: +ELLIPSIS
    5.490...
"""

from __future__ import annotations

from typing import Dict, List, Optional, Sequence

import numpy as np

from . import _realist

#: The models ``convert`` gives (``realist color --to``).
MODELS: List[str] = list(_realist.COLOR_MODELS)
#: The gamuts ``realist.chromaticity_diagram`` knows by name.
GAMUTS: List[str] = list(_realist.GAMUTS)


def convert(value: str, to: Optional[Sequence[str]] = None) -> Dict[str, List[float]]:
    """One colour in every model, as ``realist color VALUE --json`` prints it.

    ``value`` is "#rrggbb", "#rgb" or "r,g,b" (encoded sRGB floats in [0, 1]); ``to`` picks
    models from MODELS (default: all). Returns a dict from model name to its values, with
    "srgb" the colour read. ValueError for a colour or model realist does not read.
    """
    return _realist.color_convert(value, None if to is None else list(to))


def _colours(a: object) -> np.ndarray:
    arr = np.asarray(a, dtype=np.float64)
    if arr.ndim == 0 or arr.shape[-1] != 3:
        raise ValueError(f"expected colours of shape (..., 3), got {arr.shape}")
    return np.ascontiguousarray(arr)


def _map(name: str, a: object) -> np.ndarray:
    return _realist.color_map(name, _colours(a))


def srgb_to_xyz(rgb: object) -> np.ndarray:
    """Encoded sRGB to CIE XYZ (D65, Y of white = 1), with the IEC 61966-2-1 matrix."""
    return _map("srgb_to_xyz", rgb)


def xyz_to_srgb(xyz: object) -> np.ndarray:
    """CIE XYZ to encoded sRGB (not clipped: out-of-gamut colours leave [0, 1])."""
    return _map("xyz_to_srgb", xyz)


def srgb_to_lab(rgb: object) -> np.ndarray:
    """Encoded sRGB to CIE L*a*b* relative to D65."""
    return _map("srgb_to_lab", rgb)


def srgb_to_linear(rgb: object) -> np.ndarray:
    """Decodes sRGB: encoded values to linear light (the exact piecewise curve)."""
    return _map("srgb_to_linear", rgb)


def linear_to_srgb(rgb: object) -> np.ndarray:
    """Encodes linear light as sRGB (the exact piecewise curve)."""
    return _map("linear_to_srgb", rgb)


def xyz_to_lab(xyz: object) -> np.ndarray:
    """CIE XYZ to L*a*b* (white D65)."""
    return _map("xyz_to_lab", xyz)


def lab_to_xyz(lab: object) -> np.ndarray:
    """CIE L*a*b* (white D65) to XYZ."""
    return _map("lab_to_xyz", lab)


def xyz_to_luv(xyz: object) -> np.ndarray:
    """CIE XYZ to L*u*v* (white D65)."""
    return _map("xyz_to_luv", xyz)


def luv_to_xyz(luv: object) -> np.ndarray:
    """CIE L*u*v* (white D65) to XYZ."""
    return _map("luv_to_xyz", luv)


def lab_to_lch(lab: object) -> np.ndarray:
    """L*a*b* to LCh(ab): lightness, chroma, hue in degrees [0, 360)."""
    return _map("lab_to_lch", lab)


def lch_to_lab(lch: object) -> np.ndarray:
    """LCh(ab) (hue in degrees) to L*a*b*."""
    return _map("lch_to_lab", lch)


def xyz_to_xyy(xyz: object) -> np.ndarray:
    """CIE XYZ to xyY (chromaticity x, y and luminance Y)."""
    return _map("xyz_to_xyy", xyz)


def xyy_to_xyz(xyy: object) -> np.ndarray:
    """xyY to CIE XYZ."""
    return _map("xyy_to_xyz", xyy)


def rgb_to_hsv(rgb: object) -> np.ndarray:
    """RGB to HSV, hue in [0, 1)."""
    return _map("rgb_to_hsv", rgb)


def hsv_to_rgb(hsv: object) -> np.ndarray:
    """HSV (hue in [0, 1)) to RGB."""
    return _map("hsv_to_rgb", hsv)


def rgb_to_hsl(rgb: object) -> np.ndarray:
    """RGB to HSL, hue in [0, 1)."""
    return _map("rgb_to_hsl", rgb)


def _delta(kind: str, lab1: object, lab2: object) -> np.ndarray:
    return _realist.delta_e(kind, _colours(lab1), _colours(lab2))


def delta_e_1976(lab1: object, lab2: object) -> np.ndarray:
    """ΔE*ab (CIE 1976): the Euclidean distance between L*a*b* colours."""
    return _delta("1976", lab1, lab2)


def delta_e_1994(lab1: object, lab2: object) -> np.ndarray:
    """ΔE*94 (CIE 1994, graphic-arts weights); ``lab1`` is the reference (it is not symmetric)."""
    return _delta("1994", lab1, lab2)


def delta_e_2000(lab1: object, lab2: object) -> np.ndarray:
    """ΔE00 (CIEDE2000), Sharma's formulation."""
    return _delta("2000", lab1, lab2)


__all__ = [
    "GAMUTS",
    "MODELS",
    "convert",
    "delta_e_1976",
    "delta_e_1994",
    "delta_e_2000",
    "hsv_to_rgb",
    "lab_to_lch",
    "lab_to_xyz",
    "lch_to_lab",
    "linear_to_srgb",
    "luv_to_xyz",
    "rgb_to_hsl",
    "rgb_to_hsv",
    "srgb_to_lab",
    "srgb_to_linear",
    "srgb_to_xyz",
    "xyy_to_xyz",
    "xyz_to_lab",
    "xyz_to_luv",
    "xyz_to_srgb",
    "xyz_to_xyy",
]
