"""Tests of the realist Python bindings (`pip install ./python`, then `python -m pytest python/tests`).

Tests that need the shared models read the folder from the environment variable
REALIST_SHARED and are skipped, with that reason, when it is unset.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import realist
from realist import color

SHARED = os.environ.get("REALIST_SHARED")
needs_shared = pytest.mark.skipif(not SHARED, reason="needs REALIST_SHARED (the shared models)")

# A unit cube: 8 corners, 12 triangles counter-clockwise seen from outside.
CUBE_V = np.array(
    [[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)], dtype=np.float64
)
CUBE_F = np.array(
    [
        [0, 1, 3], [0, 3, 2],  # x = -1
        [4, 6, 7], [4, 7, 5],  # x = +1
        [0, 4, 5], [0, 5, 1],  # y = -1
        [2, 3, 7], [2, 7, 6],  # y = +1
        [0, 2, 6], [0, 6, 4],  # z = -1
        [1, 5, 7], [1, 7, 3],  # z = +1
    ],
    dtype=np.int64,
)


def cube() -> realist.Scene:
    return realist.Scene.from_arrays(CUBE_V, CUBE_F)


def sphere(stacks: int = 48, slices: int = 96):
    """A UV sphere of radius 1 (vertices, faces), counter-clockwise from outside."""
    th = np.linspace(0.0, np.pi, stacks + 1)
    ph = np.linspace(0.0, 2.0 * np.pi, slices, endpoint=False)
    t, p = np.meshgrid(th, ph, indexing="ij")
    v = np.stack([np.sin(t) * np.cos(p), np.cos(t), -np.sin(t) * np.sin(p)], axis=-1).reshape(-1, 3)
    faces = []
    for i in range(stacks):
        for j in range(slices):
            a, b = i * slices + j, i * slices + (j + 1) % slices
            c, d = a + slices, b + slices
            if i > 0:
                faces.append([a, c, b])
            if i < stacks - 1:
                faces.append([b, c, d])
    return v, np.array(faces, dtype=np.int64)


def resident_bytes() -> int:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


# --- arrays: shapes, dtypes, meaning ---------------------------------------------------


def test_frame_arrays_have_the_documented_shapes_and_dtypes():
    f = realist.render(cube(), size=(64, 48))
    assert f.size == (64, 48)
    assert f.rgba.shape == (48, 64, 4) and f.rgba.dtype == np.uint8
    assert f.linear.shape == (48, 64, 4) and f.linear.dtype == np.float32
    assert f.depth.shape == (48, 64) and f.depth.dtype == np.float32
    assert f.ids.shape == (48, 64) and f.ids.dtype == np.int32
    drawn = np.isfinite(f.depth)
    # The cube fills the middle of the default view, and the corners are background.
    assert drawn[24, 32] and not drawn[0, 0]
    assert 0.1 < drawn.mean() < 0.9
    assert (f.depth[drawn] > 0).all() and np.isinf(f.depth[~drawn]).all()
    # ids: the one instance where the cube is, -1 elsewhere (a ray per pixel centre agrees
    # with the rasterizer's coverage but for pixels grazing an edge).
    assert set(np.unique(f.ids)) == {-1, 0}
    assert ((f.ids == 0) == drawn).mean() > 0.99
    # rgba is the sRGB encoding of linear; alpha 255 on an opaque background.
    assert (f.rgba[..., 3] == 255).all()
    enc = np.round(color.linear_to_srgb(np.clip(f.linear[..., :3], 0, 1)) * 255)
    assert np.abs(enc - f.rgba[..., :3]).max() <= 1
    assert realist.render(cube(), size=(32, 32), ids=False).ids is None


def test_depth_is_the_distance_along_the_line_of_sight():
    cam = realist.Camera.look_at((0, 0, 5), (0, 0, 0), fov_y_degrees=40)
    f = realist.render(cube(), size=(101, 101), camera=cam)
    # The face z = +1 is 4 units in front of the eye, at every pixel it covers (view z,
    # not the distance to the eye, which grows off the axis).
    face = f.depth[np.isfinite(f.depth)]
    assert np.allclose(face, 4.0, rtol=1e-3), (face.min(), face.max())


def test_transparent_background_gives_alpha_zero_there():
    f = realist.render(cube(), size=(48, 48), background=(0, 0, 0, 0))
    drawn = np.isfinite(f.depth)
    assert (f.rgba[..., 3][~drawn] == 0).all() and (f.rgba[..., 3][drawn] > 0).all()
    g = realist.render(cube(), size=(48, 48), background="#ff000080")
    assert tuple(g.rgba[0, 0]) == (255, 0, 0, 128)


# --- from_arrays against a file ---------------------------------------------------------


def write_obj(path: Path, v: np.ndarray, f: np.ndarray) -> None:
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in v.tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in f.tolist()]
    path.write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize("shading", [None, "phong", "pbr", "flat", "gouraud"])
def test_from_arrays_renders_the_same_bytes_as_the_same_cube_from_an_obj(tmp_path, shading):
    obj = tmp_path / "cube.obj"
    write_obj(obj, CUBE_V, CUBE_F)
    cam = realist.Camera.orbit(30, 20)
    a = realist.render(cube(), size=(96, 80), camera=cam, shading=shading)
    b = realist.render(str(obj), size=(96, 80), camera=cam, shading=shading)
    c = realist.render(realist.Scene.load(obj), size=(96, 80), camera=cam, shading=shading)
    assert a.rgba.tobytes() == b.rgba.tobytes() == c.rgba.tobytes()
    assert np.array_equal(a.depth, b.depth) and np.array_equal(a.ids, b.ids)
    # float32 and int32 inputs (trimesh's dtypes) make the same scene.
    d = realist.render(
        realist.Scene.from_arrays(CUBE_V.astype(np.float32), CUBE_F.astype(np.int32)),
        size=(96, 80), camera=cam, shading=shading,
    )
    assert a.rgba.tobytes() == d.rgba.tobytes()


def test_from_arrays_takes_normals_uvs_and_colours():
    v, f = sphere(12, 24)
    uv = np.stack([np.linspace(0, 1, len(v)), np.linspace(1, 0, len(v))], axis=1)
    rgb8 = np.tile(np.array([[255, 0, 0, 255]], dtype=np.uint8), (len(v), 1))
    s = realist.Scene.from_arrays(v, f, normals=v, uvs=uv, colors=rgb8)
    assert s.instances == 1 and s.triangles == len(f) and s.source == "arrays"
    lo, hi = s.bounds
    assert np.allclose(lo, (-1, -1, -1), atol=1e-6) and np.allclose(hi, (1, 1, 1), atol=1e-6)
    fr = realist.render(s, size=(64, 64), shading="flat")
    centre = fr.linear[32, 32]
    assert centre[0] > 5 * max(centre[1], centre[2]), centre  # the vertex colour is red


# --- cameras ----------------------------------------------------------------------------


def test_intrinsics_put_a_point_where_opencv_projects_it():
    # A small cube around a world point, seen by a camera with an off-centre principal
    # point and fx != fy, posed away from the origin.
    fx, fy, cx, cy, w, h = 300.0, 260.0, 100.0, 70.0, 240, 160
    ang = 0.3
    r = np.array([[np.cos(ang), 0, np.sin(ang)], [0, 1, 0], [-np.sin(ang), 0, np.cos(ang)]])
    c2w = np.eye(4)
    c2w[:3, :3] = r
    c2w[:3, 3] = (0.5, -0.2, 1.0)
    p_cam = np.array([0.4, 0.3, 6.0])
    p_world = r @ p_cam + c2w[:3, 3]
    s = realist.Scene.from_arrays(CUBE_V * 0.05 + p_world, CUBE_F)
    cam = realist.Camera.from_intrinsics(fx, fy, cx, cy, w, h, cam_to_world=c2w)
    f = realist.render(s, camera=cam, shading="flat")
    assert f.size == (w, h)
    ys, xs = np.nonzero(np.isfinite(f.depth))
    u, v = fx * p_cam[0] / p_cam[2] + cx, fy * p_cam[1] / p_cam[2] + cy
    assert abs(xs.mean() - u) < 0.75 and abs(ys.mean() - v) < 0.75, (xs.mean(), ys.mean(), u, v)
    # The same pose as world-to-camera extrinsics gives the same image.
    g = realist.render(
        s, camera=realist.Camera.from_intrinsics(fx, fy, cx, cy, w, h, world_to_cam=np.linalg.inv(c2w)),
        shading="flat",
    )
    assert f.rgba.tobytes() == g.rgba.tobytes()
    with pytest.raises(ValueError, match="intrinsics are for a 240x160 image"):
        realist.render(s, size=(100, 100), camera=cam)
    with pytest.raises(ValueError, match="rotation"):
        realist.Camera.from_intrinsics(fx, fy, cx, cy, w, h, cam_to_world=np.diag([2.0, 1, 1, 1]))
    with pytest.raises(ValueError, match="not both"):
        realist.Camera.from_intrinsics(fx, fy, cx, cy, w, h, cam_to_world=c2w, world_to_cam=c2w)


def test_look_at_and_orbit_cameras():
    s = cube()
    a = realist.render(s, (64, 64), realist.Camera.look_at((4, 3, 5), (0, 0, 0)))
    assert np.allclose(a.camera["eye"], (4, 3, 5)) and a.camera["fov_y_degrees"] == pytest.approx(45)
    b = realist.render(s, (64, 64), realist.Camera.orbit(0, 0, 6))
    assert np.allclose(b.camera["eye"], (0, 0, 6), atol=1e-5)
    with pytest.raises(ValueError):
        realist.Camera.look_at((0, 0, 0), (0, 0, 0))
    with pytest.raises(ValueError, match="fov_y_degrees"):
        realist.Camera.look_at((0, 0, 5), (0, 0, 0), fov_y_degrees=200)


# --- threads, render_many ---------------------------------------------------------------


def test_thread_count_does_not_change_the_image():
    s = realist.Scene.from_arrays(*sphere())
    one = realist.render(s, (128, 96), threads=1, msaa=4)
    two = realist.render(s, (128, 96), threads=2, msaa=4)
    assert one.rgba.tobytes() == two.rgba.tobytes()


def test_render_many_gives_what_render_gives_in_order(tmp_path):
    obj = tmp_path / "cube.obj"
    write_obj(obj, CUBE_V, CUBE_F)
    s = cube()
    cams = [realist.Camera.orbit(a, 15) for a in (0, 90, 180)]
    items = [(s, cams[0]), (str(obj), cams[1]), s, (obj, cams[2])]
    many = realist.render_many(items, (64, 48))
    assert len(many) == 4
    for frame, (scene, cam) in zip(many, [(s, cams[0]), (obj, cams[1]), (s, None), (obj, cams[2])]):
        one = realist.render(scene, (64, 48), cam)
        assert frame.rgba.tobytes() == one.rgba.tobytes()


def free_cores() -> float:
    """How many cores two busy processes got together just now (about 2 on an idle
    two-core machine, about 1 when other work takes the rest)."""
    burn = "import time\nt = time.process_time()\nwhile time.process_time() - t < 0.3: pass\n"
    before, t = os.times(), time.perf_counter()
    procs = [subprocess.Popen([sys.executable, "-c", burn]) for _ in range(2)]
    for p in procs:
        p.wait()
    wall, after = time.perf_counter() - t, os.times()
    cpu = (after.children_user + after.children_system) - (before.children_user + before.children_system)
    return cpu / wall


def test_render_many_of_32_frames_on_2_threads_beats_a_loop_of_render():
    # Thumbnail-sized frames of a 32k-triangle sphere: a frame is one tile, so a loop of
    # render keeps a second core busy only in the frame's parallel stages, while
    # render_many's two workers render whole frames side by side.
    s = realist.Scene.from_arrays(*sphere(128, 128))
    cams = [realist.Camera.orbit(360.0 * i / 32, 20) for i in range(32)]
    size = (64, 64)
    realist.render(s, size, cams[0])  # warm-up: the environment, the ray hierarchy
    free = free_cores()
    best_loop = best_many = float("inf")
    for _ in range(5):
        t = time.perf_counter()
        loop = [realist.render(s, size, c) for c in cams]
        best_loop = min(best_loop, time.perf_counter() - t)
        t = time.perf_counter()
        many = realist.render_many([(s, c) for c in cams], size, threads=2)
        best_many = min(best_many, time.perf_counter() - t)
    free = min(free, free_cores())
    assert [f.rgba.tobytes() for f in many] == [f.rgba.tobytes() for f in loop]
    print(f"\n32 frames {size}: loop of render {best_loop * 1e3:.1f} ms, "
          f"render_many(threads=2) {best_many * 1e3:.1f} ms, ratio {best_many / best_loop:.2f} "
          f"({free:.2f} cores free)")
    if free < 1.5:
        # Two busy processes (no realist in them) got less than 1.5 cores: other work has
        # the machine, and no timing can show two threads beating one here.
        pytest.skip(f"the machine gave two busy processes only {free:.2f} cores: it is loaded")
    assert best_many < best_loop


def test_no_leak_over_1000_renders():
    v, f = sphere(8, 16)
    s = realist.Scene.from_arrays(v, f)

    def once(i: int) -> None:
        fr = realist.render(s, (64, 64), realist.Camera.orbit(i % 360, 10))
        assert fr.rgba[32, 32, 3] == 255
        if i % 10 == 0:  # a scene made and dropped, and an error raised, now and then
            realist.render(realist.Scene.from_arrays(v, f), (32, 32))
            with pytest.raises(FileNotFoundError):
                realist.render("/nonexistent/realist-leak-test.obj")

    for i in range(100):
        once(i)
    before = resident_bytes()
    for i in range(1000):
        once(i)
    after = resident_bytes()
    print(f"\nresident memory: {before / 2**20:.1f} MiB after the warm-up, "
          f"{after / 2**20:.1f} MiB after 1000 renders ({100 * (after / before - 1):+.1f}%)")
    assert after <= before * 1.10


# --- errors -----------------------------------------------------------------------------


def test_a_missing_file_raises_file_not_found_naming_it(tmp_path):
    missing = tmp_path / "no-such-model.glb"
    with pytest.raises(FileNotFoundError, match="no-such-model.glb"):
        realist.render(missing)
    with pytest.raises(FileNotFoundError, match="no-such-model.glb"):
        realist.Scene.load(missing)
    with pytest.raises(FileNotFoundError, match="render_many item 1: .*no-such-model.glb"):
        realist.render_many([cube(), missing], (16, 16))


def test_unreadable_files_raise_realist_error_naming_them(tmp_path):
    bad = tmp_path / "garbage.glb"
    bad.write_bytes(b"glTF\x02\x00\x00\x00\xff\xff\xff\x7f" + b"\x00" * 20)
    with pytest.raises(realist.RealistError, match="garbage.glb"):
        realist.render(bad)
    text = tmp_path / "words.obj"
    text.write_text("just some words\n")
    with pytest.raises(realist.RealistError, match="words.obj"):
        realist.Scene.load(text)
    with pytest.raises(realist.RealistError, match="unknown model format"):
        realist.Scene.load(tmp_path / "model.xyz")


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(vertices=np.zeros((4, 2)), faces=[[0, 1, 2]]), "vertices: expected shape"),
        (dict(vertices=CUBE_V, faces=CUBE_F[:, :2]), "faces: expected shape"),
        (dict(vertices=CUBE_V, faces=CUBE_F + 1), "refers to vertex 8, but there are 8"),
        (dict(vertices=CUBE_V, faces=-CUBE_F), "refers to vertex -"),
        (dict(vertices=CUBE_V, faces=CUBE_F.astype(float)), "faces: expected integer"),
        (dict(vertices=np.where(CUBE_V > 0, np.nan, CUBE_V), faces=CUBE_F), "not a finite number"),
        (dict(vertices=CUBE_V * 1e300, faces=CUBE_F), "not a finite number"),
        (dict(vertices=CUBE_V, faces=CUBE_F, normals=CUBE_V[:5]), "normals: expected one row per vertex"),
        (dict(vertices=CUBE_V, faces=CUBE_F, uvs=np.zeros((8, 3))), "uvs: expected shape"),
        (dict(vertices=CUBE_V, faces=CUBE_F, colors=np.zeros((8, 5))), "colors: expected shape"),
        (dict(vertices=[], faces=[]), "vertices"),
        (dict(vertices=CUBE_V, faces=np.zeros((0, 3), dtype=int)), "faces: the array is empty"),
        (dict(vertices=CUBE_V, faces=[[0, 0, 1]]), "nothing to draw"),
        (dict(vertices=[["a", "b", "c"]], faces=[[0, 0, 0]]), "vertices: expected numbers"),
    ],
)
def test_bad_arrays_raise_value_error_naming_the_problem(kwargs, message):
    with pytest.raises(ValueError, match=message):
        realist.Scene.from_arrays(**kwargs)


def test_bad_arguments_raise_value_or_type_errors():
    s = cube()
    with pytest.raises(ValueError, match="unknown shading mode 'shiny'"):
        realist.render(s, shading="shiny")
    with pytest.raises(ValueError, match="msaa"):
        realist.render(s, msaa=3)
    with pytest.raises(ValueError, match="size"):
        realist.render(s, size=(0, 10))
    with pytest.raises(ValueError, match="background"):
        realist.render(s, background="red")
    with pytest.raises(TypeError, match="realist.Scene or a path"):
        realist.render(42)
    with pytest.raises(TypeError, match="camera"):
        realist.render(s, camera="front")
    with pytest.raises(TypeError, match="a list of scenes"):
        realist.render_many("model.obj")
    with pytest.raises(ValueError, match="threads 0"):
        realist.render(s, threads=0)
    with pytest.raises(realist.RealistError, match="env /no/such.hdr"):
        realist.render(s, env="/no/such.hdr")
    assert "pbr" in realist.shading_modes()


# --- colour -----------------------------------------------------------------------------


def test_colour_functions_follow_realist_color():
    c = color.convert("#ff8000")
    assert c["srgb"] == pytest.approx([1.0, 128 / 255, 0.0])
    assert set(color.MODELS) <= set(c)
    lab = color.srgb_to_lab([1.0, 128 / 255, 0.0])
    assert lab == pytest.approx(c["lab"])
    assert color.convert("#fff", to=["xyz"])["xyz"][1] == pytest.approx(1.0, abs=1e-9)
    with pytest.raises(ValueError):
        color.convert("#ff80")
    with pytest.raises(ValueError, match="unknown model"):
        color.convert("#ff8000", to=["nope"])
    img = np.random.default_rng(1).random((4, 5, 3))
    xyz = color.srgb_to_xyz(img)
    assert xyz.shape == (4, 5, 3)
    # The IEC matrices are rounded to four places: their round trip is close, not exact.
    assert np.allclose(color.xyz_to_srgb(xyz), img, atol=2e-4)
    assert np.allclose(color.linear_to_srgb(color.srgb_to_linear(img)), img, atol=1e-9)
    labs = color.xyz_to_lab(xyz)
    assert np.allclose(color.lab_to_xyz(labs), xyz, atol=1e-9)
    de = color.delta_e_2000(labs, labs[::-1])
    assert de.shape == (4, 5) and (de >= 0).all()
    assert np.allclose(color.delta_e_2000(labs, labs), 0)
    # Sharma's first CIEDE2000 test pair.
    assert color.delta_e_2000([50, 2.6772, -79.7751], [50, 0, -82.7485]) == pytest.approx(2.0425, abs=1e-4)
    with pytest.raises(ValueError):
        color.srgb_to_xyz(np.zeros((4, 2)))


def test_chromaticity_diagram_is_an_rgba_array():
    d = realist.chromaticity_diagram(256, gamuts=["srgb", "display-p3"], points=[(0.3127, 0.329, "D65")])
    assert d.shape == (256, 256, 4) and d.dtype == np.uint8
    assert (d[..., 3] > 0).mean() > 0.5
    # The horseshoe is coloured: some pixels are far from grey.
    rgb = d[..., :3].astype(int)
    assert (rgb.max(axis=-1) - rgb.min(axis=-1)).max() > 100
    custom = realist.chromaticity_diagram(128, gamuts=[(0.7, 0.3, 0.2, 0.7, 0.15, 0.05)], plane="u'v'")
    assert custom.shape == (128, 128, 4)
    with pytest.raises(ValueError, match="unknown gamut"):
        realist.chromaticity_diagram(256, gamuts=["nope"])
    with pytest.raises(ValueError, match="size"):
        realist.chromaticity_diagram(16)


# --- the shared models ------------------------------------------------------------------


@needs_shared
def test_shared_models_render_with_pbr_and_textures():
    root = Path(SHARED) / "models"
    box = realist.render(root / "gltf" / "Box.glb", (128, 96))
    assert np.isfinite(box.depth).mean() > 0.1
    spot = realist.Scene.load(root / "obj" / "spot.obj")
    frames = realist.render_many(
        [(spot, realist.Camera.orbit(a, 10)) for a in range(0, 360, 45)]
        + [root / "obj" / "stanford-bunny.obj"],
        (96, 96),
    )
    assert len(frames) == 9
    for f in frames:
        assert np.isfinite(f.depth).mean() > 0.05 and (f.ids[np.isfinite(f.depth)] >= 0).mean() > 0.95


@needs_shared
def test_malformed_files_raise_and_never_crash():
    corpus = Path(SHARED) / "corpus" / "obj-malformed"
    files = sorted(p for p in corpus.iterdir() if p.suffix == ".obj")
    assert files
    raised = 0
    for p in files:
        try:
            realist.render(p, (32, 32))
        except realist.RealistError as e:
            assert p.name in str(e), (p, e)
            raised += 1
    assert raised > 0
