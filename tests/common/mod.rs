//! Helpers shared by the integration tests: small scenes, rendering, golden-image comparison
//! with named tolerances and a diff image on failure (`REPLACE=1` rewrites the goldens).

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::sync::Arc;

use base64::Engine as _;
use glam::{Mat4, Vec2, Vec3, Vec4};
use realist::mesh::{Channel, Mesh, MeshData, NormalPolicy};
use realist::raster::Framebuffer;
use realist::render::{PreparedScene, Renderer, Settings, Shot};
use realist::scene::{Camera, Instance, Light, Material, Scene, Style, TextureSlot};
use realist::shade::Shading;
use realist::simd::KernelKind;
use realist::texture::{Sampler, Texture};

/// How far a rendered image may be from its golden.
#[derive(Clone, Copy, Debug)]
pub struct Tolerance {
    /// Largest per-channel difference (8-bit sRGB codes) that does not count as differing.
    pub max_channel: u8,
    /// Fraction of pixels allowed to differ by more than `max_channel`.
    pub max_fraction: f64,
}

/// Shaded images: deterministic here, but `powf` and friends may differ in the last bit
/// between platforms' libm, which moves a code value on rare pixels.
pub const SHADED: Tolerance = Tolerance {
    max_channel: 2,
    max_fraction: 0.002,
};
/// Coverage-only images (wireframe, flat colours): exact.
pub const EXACT: Tolerance = Tolerance {
    max_channel: 0,
    max_fraction: 0.0,
};

/// A scene with one instance of `mesh` using `material`.
pub fn scene_of(mut mesh: Mesh, material: Material) -> Scene {
    let mut scene = Scene::default();
    mesh.material = Some(0);
    scene.materials.push(material);
    scene.meshes.push(mesh);
    scene.instances.push(Instance {
        mesh: 0,
        world: Mat4::IDENTITY,
        name: "test".into(),
        style: Style::Inherit,
        node: None,
        skin: None,
        copies: None,
    });
    scene
}

/// A mesh from raw triangles (positions, triangle corners), averaged normals.
pub fn triangles(positions: Vec<Vec3>, corners: Vec<u32>) -> Mesh {
    let data = MeshData {
        name: "tris".into(),
        positions,
        corners,
        ..MeshData::default()
    };
    Mesh::new(data, NormalPolicy::default()).expect("valid test mesh")
}

/// The chequered cube: a unit cube with an 8x8 chequer texture as base colour.
pub fn checker_cube() -> Scene {
    let mut scene = scene_of(
        Mesh::cube(1.6).expect("cube"),
        Material {
            base_color: Vec4::ONE,
            base_color_texture: Some(TextureSlot::new(0)),
            ..Material::default()
        },
    );
    scene.textures.push(Arc::new(Texture::checker(
        64,
        8,
        [230, 230, 230, 255],
        [40, 90, 200, 255],
    )));
    scene
}

/// Renders with explicit options; the frame and statistics of a pool of `threads` threads
/// are returned (see [`render_prepared`]: every kernel on 1, 2 and 3 threads must agree).
pub fn render_with(
    scene: &Scene,
    opts: &Shot,
    threads: usize,
) -> (Framebuffer, realist::raster::Stats) {
    let prepared = PreparedScene::new(scene.clone());
    let view = opts.view(prepared.scene());
    render_prepared(&prepared, &opts.settings, &view, threads)
}

/// The thread counts every golden is rendered on (issue 39: the same image on every
/// machine, whatever its cores).
pub const THREAD_COUNTS: [usize; 3] = [1, 2, 3];

/// Renders `prepared` with every kernel this machine has, each on 1, 2 and 3 threads, and
/// asserts that every frame is the same to the bit, colour and depth (no fused
/// multiply-add, no approximate instruction, no platform libm, tiles that do not depend on
/// the thread count: README, "The same image on every machine"). Returns the frame and the
/// statistics of the portable kernel on `threads` threads.
pub fn render_prepared(
    prepared: &PreparedScene,
    settings: &Settings,
    view: &realist::render::View,
    threads: usize,
) -> (Framebuffer, realist::raster::Stats) {
    let bits = |fb: &Framebuffer| -> Vec<u32> {
        let c = fb.color.iter().flat_map(|c| c.to_array());
        c.chain(fb.depth.iter().copied())
            .map(f32::to_bits)
            .collect()
    };
    let mut first: Option<(Vec<u32>, u64, String)> = None;
    let mut wanted = None;
    for n in THREAD_COUNTS
        .into_iter()
        .chain((!THREAD_COUNTS.contains(&threads)).then_some(threads))
    {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .expect("thread pool");
        for kernel in KernelKind::available_kinds() {
            let (fb, stats) = pool.install(|| {
                let mut renderer = Renderer::new();
                let settings = Settings {
                    kernel: Some(kernel),
                    ..settings.clone()
                };
                let stats = renderer.render(prepared, &settings, view).stats;
                (renderer.take_target().expect("a frame").resolve(), stats)
            });
            let got = bits(&fb);
            let what = format!("{kernel:?} on {n} thread(s)");
            match &first {
                None => first = Some((got, stats.pixels_shaded, what)),
                Some((want, shaded, first_what)) => {
                    assert_eq!(*shaded, stats.pixels_shaded, "{what} against {first_what}");
                    let differ = want.iter().zip(&got).filter(|(x, y)| x != y).count();
                    assert_eq!(
                        differ, 0,
                        "{what}: {differ} values differ from {first_what}'s"
                    );
                }
            }
            if n == threads && wanted.is_none() {
                wanted = Some((fb, stats));
            }
        }
    }
    wanted.expect("the portable kernel is always available")
}

/// Renders `scene` at `w` x `h` with a mode (None = the scene's styles) and optional camera.
pub fn render(
    scene: &Scene,
    w: u32,
    h: u32,
    shading: Option<Shading>,
    camera: Option<Camera>,
) -> Framebuffer {
    let opts = Shot {
        width: w,
        height: h,
        camera,
        settings: Settings {
            shading,
            ..Settings::default()
        },
    };
    render_with(scene, &opts, 2).0
}

/// Asserts that no pixel of colour or depth is NaN or infinite.
pub fn assert_finite(fb: &Framebuffer, what: &str) {
    let bad = fb.color.iter().filter(|c| !c.is_finite()).count();
    assert_eq!(bad, 0, "{what}: {bad} non-finite colour pixels");
    let bad = fb.depth.iter().filter(|d| !d.is_finite()).count();
    assert_eq!(bad, 0, "{what}: {bad} non-finite depth pixels");
}

/// Number of pixels whose colour differs from the background.
pub fn covered(fb: &Framebuffer) -> usize {
    let bg = Shot::default().settings.background;
    fb.color.iter().filter(|c| **c != bg).count()
}

fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("golden")
}

/// Compares `fb` (sRGB-encoded) with `tests/golden/NAME.png`. On failure writes the image and
/// a diff (differences scaled x16, red where above tolerance) to `target/golden-diff/` and
/// panics with the figures. With `REPLACE=1` (or when the golden is missing and `REPLACE`
/// is set), writes the golden instead.
pub fn check_golden(name: &str, fb: &Framebuffer, tol: Tolerance) {
    check_golden_rgb(name, fb.width, fb.height, fb.to_srgb8(), tol);
}

/// Where [`check_golden_rgb`] records each rendered golden's hash: one file per golden
/// (`NAME.txt`: the FNV-1a 64 hash of its RGB8 bytes, its size and name), which `.ci/run`
/// prints, so two machines' images can be compared without the images.
pub fn golden_hash_dir() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("golden-hashes")
}

/// FNV-1a, 64 bits: a small hash with the same value on every machine.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// [`check_golden`] for any `w` x `h` RGB8 image.
pub fn check_golden_rgb(name: &str, w: u32, h: u32, got: Vec<u8>, tol: Tolerance) {
    let path = golden_dir().join(format!("{name}.png"));
    let hashes = golden_hash_dir();
    std::fs::create_dir_all(&hashes).expect("golden hash dir");
    std::fs::write(
        hashes.join(format!("{name}.txt")),
        format!("{:016x} {w}x{h} {name}\n", fnv1a64(&got)),
    )
    .expect("record the golden's hash");
    if std::env::var_os("REPLACE").is_some() {
        std::fs::create_dir_all(golden_dir()).expect("golden dir");
        realist::color::png::Png::rgb(w, h, &got)
            .with_text("Source", format!("golden {name}"))
            .write(&path)
            .expect("write golden");
        eprintln!("wrote golden {}", path.display());
        return;
    }
    let want = image::open(&path)
        .unwrap_or_else(|e| {
            panic!(
                "golden {} unreadable ({e}); run with REPLACE=1 to create it",
                path.display()
            )
        })
        .to_rgb8();
    assert_eq!(
        (want.width(), want.height()),
        (w, h),
        "golden {name} has a different size"
    );
    let mut diff = vec![0u8; got.len()];
    let mut over = 0usize;
    let mut worst = 0u8;
    for (p, (a, b)) in got.chunks(3).zip(want.as_raw().chunks(3)).enumerate() {
        let d = a
            .iter()
            .zip(b)
            .map(|(x, y)| x.abs_diff(*y))
            .max()
            .unwrap_or(0);
        worst = worst.max(d);
        if d > tol.max_channel {
            over += 1;
            diff[p * 3] = 255;
        } else {
            diff[p * 3 + 1] = d.saturating_mul(16);
        }
    }
    let fraction = over as f64 / (w * h) as f64;
    if fraction > tol.max_fraction {
        let out = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("target")
            .join("golden-diff");
        std::fs::create_dir_all(&out).expect("diff dir");
        let _ = realist::color::png::Png::rgb(w, h, &got).write(&out.join(format!("{name}.png")));
        let _ =
            realist::color::png::Png::rgb(w, h, &diff).write(&out.join(format!("{name}-diff.png")));
        panic!(
            "golden {name}: {over} pixels ({:.4}%) differ by more than {} (worst {worst}); allowed {:.4}%. See {}",
            fraction * 100.0,
            tol.max_channel,
            tol.max_fraction * 100.0,
            out.display()
        );
    }
}

/// A unit cube (24 vertices with normals, 36 u16 indices) as a buffer.
pub fn cube_buffer() -> (Vec<u8>, usize, usize) {
    let mut pos = Vec::new();
    let mut nrm = Vec::new();
    let mut idx: Vec<u16> = Vec::new();
    let faces = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    for n in faces {
        let u = if n.y.abs() > 0.5 { Vec3::X } else { Vec3::Y };
        let v = n.cross(u);
        let base = pos.len() as u16;
        for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            pos.push(n * 0.5 + u * (0.5 * a) + v * (0.5 * b));
            nrm.push(n);
        }
        // (u, v, n) is right-handed, so counter-clockwise in (u, v) faces +n.
        idx.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    let mut bytes = Vec::new();
    for p in pos.iter().chain(&nrm) {
        for c in p.to_array() {
            bytes.extend(c.to_le_bytes());
        }
    }
    let idx_offset = bytes.len();
    for i in &idx {
        bytes.extend(i.to_le_bytes());
    }
    (bytes, idx_offset, idx.len())
}

/// Writes `nodes.gltf` into `dir`: see [`gltf_json`].
pub fn write_gltf(dir: &std::path::Path, root: &str, child: &str) -> std::path::PathBuf {
    let path = dir.join("nodes.gltf");
    std::fs::write(&path, gltf_json(root, child)).expect("write gltf");
    path
}

/// A glTF (buffer as a data URI) whose scene has `root` with `child` below it, the child
/// drawing the cube; `root` and `child` are extra JSON members of the two nodes.
pub fn gltf_json(root: &str, child: &str) -> String {
    let (bytes, idx_offset, idx_count) = cube_buffer();
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&bytes)
    );
    let json = format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  "scene": 0,
  "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"children": [1], {root}}}, {{"mesh": 0, {child}}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1}}, "indices": 2}}]}}],
  "buffers": [{{"byteLength": {len}, "uri": "{uri}"}}],
  "bufferViews": [
    {{"buffer": 0, "byteOffset": 0, "byteLength": 576}},
    {{"buffer": 0, "byteOffset": {idx_offset}, "byteLength": {idx_len}}}
  ],
  "accessors": [
    {{"bufferView": 0, "byteOffset": 0, "componentType": 5126, "count": 24, "type": "VEC3", "min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5]}},
    {{"bufferView": 0, "byteOffset": 288, "componentType": 5126, "count": 24, "type": "VEC3"}},
    {{"bufferView": 1, "componentType": 5123, "count": {idx_count}, "type": "SCALAR"}}
  ]
}}"#,
        len = bytes.len(),
        idx_len = idx_count * 2,
    );
    json
}

/// The JSON chunk of a GLB file, parsed, and where its binary chunk's data starts.
pub fn glb_parts(bytes: &[u8]) -> (serde_json::Value, usize) {
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().expect("GLB header")) as usize;
    let json = serde_json::from_slice(&bytes[20..20 + json_len]).expect("GLB JSON chunk");
    (json, 20 + json_len + 8)
}

/// The GLB file `src` written to `dest` with the bytes `range` of its binary chunk inverted.
pub fn write_inverted_glb(src: &Path, range: std::ops::Range<usize>, dest: &Path) {
    let mut bytes = std::fs::read(src).unwrap_or_else(|e| panic!("{}: {e}", src.display()));
    let (_, bin) = glb_parts(&bytes);
    for b in &mut bytes[bin + range.start..bin + range.end] {
        *b = !*b;
    }
    std::fs::write(dest, bytes).unwrap_or_else(|e| panic!("{}: {e}", dest.display()));
}

/// The byte range, in the binary chunk, of the compressed data of meshopt bufferView `view`
/// (`EXT_` or `KHR_meshopt_compression`) of the GLB `bytes`.
pub fn meshopt_range(bytes: &[u8], view: usize) -> std::ops::Range<usize> {
    let (json, _) = glb_parts(bytes);
    let v = &json["bufferViews"][view]["extensions"];
    let e = v
        .as_object()
        .expect("a meshopt view")
        .values()
        .next()
        .expect("an extension");
    let start = e["byteOffset"].as_u64().unwrap_or(0) as usize;
    start..start + e["byteLength"].as_u64().expect("byteLength") as usize
}

/// The byte range, in the binary chunk, of bufferView `view` of the GLB's JSON `json`.
pub fn view_range(json: &serde_json::Value, view: usize) -> std::ops::Range<usize> {
    let v = &json["bufferViews"][view];
    let start = v["byteOffset"].as_u64().unwrap_or(0) as usize;
    start..start + v["byteLength"].as_u64().expect("byteLength") as usize
}

pub fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("realist-test-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// colour-science's reference values, `$REALIST_SHARED/color/reference.json` (for tests
/// marked as needing `REALIST_SHARED`: see [`realist_testkit::shared`]).
pub fn colour_reference(what: &str) -> serde_json::Value {
    let path = realist_testkit::shared(what).join("color/reference.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// One quad (two triangles) with per-vertex UVs and normal `normal`, textured with `texture`
/// read by `sampler` (base colour white, no specular) and lit along `-normal`.
pub fn textured_quad(
    corners: [Vec3; 4],
    uvs: [Vec2; 4],
    normal: Vec3,
    texture: Texture,
    sampler: Sampler,
) -> Scene {
    let data = MeshData {
        name: "quad".into(),
        positions: corners.to_vec(),
        corners: vec![0, 1, 2, 0, 2, 3],
        normals: Some(Channel::per_vertex(vec![normal; 4])),
        uvs: vec![Channel::per_vertex(uvs.to_vec())],
        ..MeshData::default()
    };
    let mesh = Mesh::new(data, NormalPolicy::default()).expect("quad");
    let mut scene = scene_of(
        mesh,
        Material {
            base_color: Vec4::ONE,
            base_color_texture: Some(TextureSlot {
                sampler,
                ..TextureSlot::new(0)
            }),
            specular: Vec3::ZERO,
            ..Material::default()
        },
    );
    scene.textures.push(Arc::new(texture));
    scene.lights = vec![Light::directional(-normal, Vec3::ONE)];
    scene
}
