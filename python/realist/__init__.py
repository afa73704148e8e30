"""realist: render glTF, OBJ, STL and PLY models on the CPU into numpy arrays.

No GPU, no display and no driver: the renderer is realist's tiled rasterizer, written in
Rust. The GIL is released while it works, and ``render_many`` renders a list of frames at
once over every core.

    >>> import realist
    >>> frame = realist.render("model.glb", size=(640, 480))
    >>> frame.rgba.shape, frame.rgba.dtype
    ((480, 640, 4), dtype('uint8'))

See ``realist.Scene`` (models from files or numpy arrays), ``realist.Camera`` (look-at,
orbit, and calibrated cameras from intrinsics), ``realist.render``, ``realist.render_many``,
``realist.color`` (the colour toolkit over numpy arrays) and
``realist.chromaticity_diagram``.
"""

from __future__ import annotations

from . import _realist
from ._realist import (
    Camera,
    Frame,
    RealistError,
    Scene,
    __version__,
    chromaticity_diagram,
    render,
    render_many,
    shading_modes,
)
from . import color

__all__ = [
    "Camera",
    "Frame",
    "RealistError",
    "Scene",
    "chromaticity_diagram",
    "color",
    "render",
    "render_many",
    "shading_modes",
    "__version__",
]
