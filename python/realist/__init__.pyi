"""Typed interface of realist: render glTF, OBJ, STL and PLY models on the CPU into numpy arrays."""

import os
from typing import Dict, List, Literal, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import color as color

__version__: str

PathLike = Union[str, "os.PathLike[str]"]
ArrayLike = npt.ArrayLike
Vec3 = Tuple[float, float, float]
#: A render_many item: a scene or a path, alone or with its camera.
Item = Union["Scene", PathLike, Tuple[Union["Scene", PathLike], Optional["Camera"]]]
Shading = Literal[
    "wireframe", "flat", "gouraud", "phong", "blinn", "textured", "pbr", "whitted", "path",
    "radiosity", "normals", "depth", "uv", "uv-checker", "mip-level", "texel-density",
    "anisotropy", "tangents", "tangent-normals",
]

class RealistError(Exception):
    """An error from realist (a file it cannot read, a render that failed); the message is realist's."""

class Scene:
    """A scene ready to render: a model file loaded, or a triangle mesh made from numpy
    arrays, prepared once and shared by every render that uses it. Immutable; safe to share
    between threads."""

    @staticmethod
    def load(path: PathLike) -> Scene:
        """Loads a model file (.obj, .gltf, .glb, .stl, .ply) as ``realist render`` does.

        Raises FileNotFoundError for a missing file and RealistError for a file realist
        cannot read (the message names the file and the problem)."""
    @staticmethod
    def from_arrays(
        vertices: ArrayLike,
        faces: ArrayLike,
        normals: Optional[ArrayLike] = None,
        uvs: Optional[ArrayLike] = None,
        colors: Optional[ArrayLike] = None,
    ) -> Scene:
        """A triangle mesh from numpy arrays (trimesh's vertices and faces work as they are).

        vertices: (n, 3) floats; faces: (m, 3) integer vertex indices (counter-clockwise
        seen from the front); normals: (n, 3) per-vertex normals (default: averaged from the
        faces, as for an OBJ file without normals); uvs: (n, 2) texture coordinates with the
        origin at the bottom left (OBJ's and trimesh's convention); colors: (n, 3) or (n, 4)
        per-vertex colours, floats in linear light or uint8 sRGB (trimesh's). Values must be
        finite and indices in range: ValueError names the array and the problem. The mesh
        gets realist's default material, as an OBJ file without a material library does."""
    @property
    def source(self) -> str:
        """The file the scene was loaded from, or "arrays"."""
    @property
    def bounds(self) -> Optional[Tuple[Vec3, Vec3]]:
        """((xmin, ymin, zmin), (xmax, ymax, zmax)) of everything drawn, or None."""
    @property
    def triangles(self) -> int:
        """How many triangles the scene draws (every instance counted)."""
    @property
    def instances(self) -> int:
        """How many instances (placed meshes) the scene has: ``Frame.ids`` numbers them."""
    @property
    def warnings(self) -> List[str]:
        """What the loader could not use or changed (missing textures, dropped faces, ...)."""

class Camera:
    """A camera for ``render``: make one with ``look_at``, ``orbit`` or ``from_intrinsics``."""

    @staticmethod
    def look_at(
        eye: Vec3,
        target: Vec3,
        up: Vec3 = (0.0, 1.0, 0.0),
        fov_y_degrees: float = 45.0,
        near: Optional[float] = None,
        far: Optional[float] = None,
    ) -> Camera:
        """A perspective camera at ``eye`` looking at ``target``, ``up`` upwards on the
        screen, with a vertical field of view in degrees. ``near`` and ``far`` (distances
        along the line of sight) are fitted to the scene's bounds unless both are given."""
    @staticmethod
    def orbit(
        azimuth: float,
        elevation: float,
        distance: Optional[float] = None,
        fov_y_degrees: Optional[float] = None,
    ) -> Camera:
        """``realist render --camera AZ,EL[,DIST]``: orbiting the scene's centre, ``azimuth``
        degrees around the up axis (0 looks down -Z from +Z) and ``elevation`` degrees above
        the horizon; the distance frames the scene unless given."""
    @staticmethod
    def from_intrinsics(
        fx: float,
        fy: float,
        cx: float,
        cy: float,
        width: int,
        height: int,
        cam_to_world: Optional[npt.NDArray[np.floating]] = None,
        world_to_cam: Optional[npt.NDArray[np.floating]] = None,
        near: Optional[float] = None,
        far: Optional[float] = None,
    ) -> Camera:
        """A calibrated pinhole camera in OpenCV's convention: focal lengths and principal
        point in pixels of a ``width`` x ``height`` image (the centre of the top-left pixel
        is (0, 0)); camera x right, y down, z forward.

        The pose is a 4x4 rigid transform given as one of ``cam_to_world`` (the camera's
        axes and position in world coordinates, as NeRF-style datasets store it) or
        ``world_to_cam`` (OpenCV's extrinsics [R | t], as cv2.solvePnP and COLMAP give them);
        neither is the identity. A world point X lands at pixel (fx x / z + cx, fy y / z + cy)
        where (x, y, z) = world_to_cam @ X. Renders with this camera must be width x height
        (the default size). ``near`` and ``far`` are fitted to the scene unless both given."""
    @property
    def size(self) -> Optional[Tuple[int, int]]:
        """The image size a camera from intrinsics was calibrated for, else None."""

class Frame:
    """A rendered image and its buffers as numpy arrays (rows top first, C order)."""

    @property
    def rgba(self) -> npt.NDArray[np.uint8]:
        """(height, width, 4) uint8: 8-bit sRGB, the bytes ``realist render`` writes to a
        PNG, plus alpha (linear alpha times 255, rounded)."""
    @property
    def linear(self) -> npt.NDArray[np.float32]:
        """(height, width, 4) float32 linear-light RGBA: after exposure and the tone map,
        before the sRGB encoding of ``rgba``."""
    @property
    def depth(self) -> npt.NDArray[np.float32]:
        """(height, width) float32: the distance in front of the camera along its line of
        sight (view-space z, as OpenCV depth maps measure it, not the distance to the eye);
        infinity where nothing was drawn."""
    @property
    def ids(self) -> Optional[npt.NDArray[np.int32]]:
        """(height, width) int32: the scene instance seen at each pixel centre (0 to
        Scene.instances - 1), -1 for the background and the ground plane; None when
        rendered with ids=False."""
    @property
    def size(self) -> Tuple[int, int]:
        """(width, height) in pixels."""
    @property
    def camera(self) -> Dict[str, object]:
        """The camera used: eye, target, up (world coordinates) and fov_y_degrees."""

def render(
    scene: Union[Scene, PathLike],
    size: Optional[Tuple[int, int]] = None,
    camera: Optional[Camera] = None,
    *,
    shading: Optional[Shading] = None,
    env: Optional[str] = None,
    env_background: Optional[float] = None,
    background: Union[None, str, Tuple[float, float, float], Tuple[float, float, float, float]] = None,
    msaa: Literal[1, 4] = 1,
    samples: int = 1,
    exposure: Optional[float] = None,
    tone: Optional[str] = None,
    double_sided: bool = False,
    ground: bool = False,
    shadows: bool = False,
    up: Literal["y", "z"] = "y",
    ids: bool = True,
    threads: Optional[int] = None,
) -> Frame:
    """Renders one frame of a model file or a Scene, as ``realist render`` would.

    size: (width, height), default the camera's (intrinsics) or 1280x720. camera: default
    the scene framed from a three-quarter view. shading: a mode of ``shading_modes()``
    (default: pbr for glTF materials, textured for a model with textures, else phong).
    env: the environment lighting pbr ("default" or None: the studio; "none", "studio",
    "sky", "uniform", or an .hdr/.exr path); env_background shows it behind the model,
    blurred to that roughness. background: linear (r, g, b[, a]) floats or "#rrggbb[aa]"
    (sRGB); an alpha below 1 makes the background transparent in ``rgba``. msaa 1 or 4;
    samples: N x N supersampling (1 to 8); exposure in EV; tone: clamp, scale-max,
    reinhard, pbr-neutral, aces-narkowicz, aces-hill or auto. up: the world's up axis for the
    default and orbit cameras. ids=False skips ``Frame.ids``. threads: worker threads
    (default every core); the image is the same for any count.

    The GIL is released while rendering. Errors raise: FileNotFoundError for a missing
    file, RealistError for a file realist cannot read, ValueError for a bad argument."""

def render_many(
    items: Sequence[Item],
    size: Optional[Tuple[int, int]] = None,
    *,
    shading: Optional[Shading] = None,
    env: Optional[str] = None,
    env_background: Optional[float] = None,
    background: Union[None, str, Tuple[float, float, float], Tuple[float, float, float, float]] = None,
    msaa: Literal[1, 4] = 1,
    samples: int = 1,
    exposure: Optional[float] = None,
    tone: Optional[str] = None,
    double_sided: bool = False,
    ground: bool = False,
    shadows: bool = False,
    up: Literal["y", "z"] = "y",
    ids: bool = True,
    threads: Optional[int] = None,
) -> List[Frame]:
    """Renders many frames at once over every core (or ``threads``), with the GIL released.

    items: Scenes or paths, or (Scene or path, Camera) pairs; the keyword arguments are
    ``render``'s, applied to every frame. Returns the Frames in the order of ``items``
    (each the same as ``render`` would give). With at least as many items as threads, each
    thread renders whole frames one after another; with fewer, the frames are rendered one
    after another, each over every thread. A failing item raises, naming its index."""

def shading_modes() -> List[str]:
    """The names ``shading=`` takes, in the order ``realist render --help`` lists them."""

def chromaticity_diagram(
    size: int = 1024,
    gamuts: Optional[Sequence[Union[str, Sequence[float]]]] = None,
    points: Optional[Sequence[Union[Tuple[float, float], Tuple[float, float, str]]]] = None,
    *,
    plane: Literal["xy", "uv", "u'v'"] = "xy",
    observer: Literal["1931", "1964"] = "1931",
    whites: Optional[Sequence[str]] = None,
    planckian: bool = False,
    fill: Literal["smooth", "colour-science", "none"] = "smooth",
    title: Optional[str] = None,
) -> npt.NDArray[np.uint8]:
    """The CIE chromaticity diagram of ``realist chroma`` as a (size, size, 4) uint8
    straight-alpha sRGB image (128 to 8192 pixels).

    gamuts: names of ``color.GAMUTS`` (srgb, display-p3, rec2020, ...) or six numbers (the
    xy chromaticities of red, green and blue; white D65); points: (x, y) or (x, y, label)
    chromaticities to mark; whites: illuminants to mark (a, c, d50, d65, e); planckian:
    draw the Planckian locus with iso-temperature ticks."""
