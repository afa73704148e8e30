//! The Khronos texture samples in `$REALIST_SHARED/models/gltf/khronos/` render as their
//! authors intend (reported as ignored when `REALIST_SHARED` is unset):
//!
//! - `TextureCoordinateTest`: four squares, each showing its corner of one texture (a
//!   chequered corner mark and the label "Top Left", ..., "Bottom Right") upright, tinted
//!   by its material's colour, in front of a grey plane.
//! - `TextureSettingsTest`: quads whose UVs run outside [0, 1] so that only the sampler's
//!   wrap mode (repeat, mirrored repeat or clamp, per axis S = u and T = v) brings a green
//!   tick into view; a wrong mode shows a red cross. Two more rows test single- and
//!   double-sided drawing the same way. Red never shows when everything is right.
//! - `MultiUVTest`: a cube with a base-colour texture on `TEXCOORD_0` and an emissive texture
//!   on `TEXCOORD_1`, whose set-1 UVs stay in the corner with the glTF logo; read through
//!   `TEXCOORD_0` the emissive map would write "Multiple UVs not supported in this viewer".
//!
//! Every check predicts pixels independently of the renderer: a ray through each pixel
//! centre (from the camera's inverse view-projection) is intersected with the loaded
//! triangles here, the hit's barycentric coordinates interpolate the file's UVs, the wrap
//! mode (taken from the sampler names written in the file) folds them, and the texel of the
//! decoded image there, times the material's factor, is the prediction. For that the
//! frames compared pixel by pixel are drawn with every slot's filter set to nearest (the
//! pixel is then exactly one texel; what is tested is which texel, i.e. UVs and wrapping),
//! and pixels on an instance's outline are left out. The "red never shows" check uses the
//! file's own filters. Each test also shows the comparison has teeth: a plausible wrong
//! reading (a flipped v, the other UV set, repeat for every sampler) must miss.
//!
//! The scenes are lit by one ambient light of 1 on non-specular materials, so a lit pixel
//! is texel x factor (+ emission).

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3, Vec4};

use realist::load::{load, LoadOptions};
use realist::raster::Framebuffer;
use realist::render::{render, Lights, PreparedScene, Settings, Shot};
use realist::scene::{Camera, Light, Scene, Slot};
use realist::shade::Shading;
use realist::texture::{Filter, Texture, Wrap};

/// The Khronos sample `name` in the shared test data (for tests marked as needing it),
/// loaded and made matte.
fn khronos(name: &str) -> Scene {
    let path = realist_testkit::shared(name)
        .join("models/gltf/khronos")
        .join(name)
        .join(format!("{name}.gltf"));
    let scene = load(&path, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    matte(scene, &path)
}

/// Every material made a matte dielectric of the file's own `baseColorFactor`: specular
/// off, ambient reflectance 1, not metallic (textures kept).
///
/// TextureCoordinateTest and MultiUVTest leave `metallicFactor` out, which glTF reads as
/// 1, a metal: the loader's Phong conversion then has no diffuse colour (`K_d = base (1 -
/// metallic)`), and they render black but for highlights (a PBR viewer shows them by its
/// environment's reflections). The factor is read back from the file, so that the texture
/// mapping shows under an ambient light.
fn matte(mut scene: Scene, path: &std::path::Path) -> Scene {
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let materials = json["materials"].as_array().cloned().unwrap_or_default();
    assert_eq!(
        materials.len(),
        scene.materials.len(),
        "one material per file material"
    );
    for m in &mut scene.materials {
        let file = materials
            .iter()
            .find(|f| f["name"].as_str() == Some(m.name.as_str()))
            .unwrap_or_else(|| panic!("material '{}' is not in the file", m.name));
        let factor = &file["pbrMetallicRoughness"]["baseColorFactor"];
        m.base_color = match factor.as_array() {
            Some(f) => Vec4::from_array(std::array::from_fn(|i| f[i].as_f64().unwrap() as f32)),
            None => Vec4::ONE,
        };
        m.specular = Vec3::ZERO;
        m.ambient = Vec3::ONE;
        m.metallic = 0.0;
    }
    scene
}

/// Every texture slot read with nearest filtering.
fn nearest(mut scene: Scene) -> Scene {
    for m in &mut scene.materials {
        for slot in Slot::ALL {
            if let Some(s) = m.slot_mut(slot) {
                s.sampler.filter = Filter::Nearest;
            }
        }
    }
    scene
}

fn draw(scene: &Scene, camera: &Camera, w: u32, h: u32) -> Framebuffer {
    let opts = Shot {
        width: w,
        height: h,
        camera: Some(camera.clone()),
        settings: Settings {
            shading: Some(Shading::Textured),
            lights: Lights::Custom {
                lights: vec![Light::ambient(Vec3::ONE)],
                follow_camera: false,
            },
            ..Settings::default()
        },
    };
    render(&PreparedScene::new(scene.clone()), &opts).image()
}

/// What the ray through a pixel centre meets first.
struct Hit {
    instance: usize,
    /// UV of every set of the mesh at the point.
    uvs: Vec<Vec2>,
}

/// The pixel centre's ray `(origin on the near plane, direction)` for `camera` in a `w` x
/// `h` frame (the projection is reversed-Z: depth 1 on the near plane).
fn ray(camera: &Camera, w: u32, h: u32, x: f32, y: f32) -> (Vec3, Vec3) {
    let vp: Mat4 = camera.projection(w as f32 / h as f32) * camera.view();
    let inv = vp.inverse();
    let ndc = Vec2::new(
        (x + 0.5) / w as f32 * 2.0 - 1.0,
        1.0 - (y + 0.5) / h as f32 * 2.0,
    );
    let near = inv.project_point3(ndc.extend(1.0));
    let further = inv.project_point3(ndc.extend(0.5));
    (near, (further - near).normalize())
}

/// The first triangle the ray meets that the renderer draws from that side (single-sided
/// materials are culled from behind).
fn cast(scene: &Scene, origin: Vec3, dir: Vec3) -> Option<Hit> {
    let mut best: Option<(f32, Hit)> = None;
    for (i, inst) in scene.instances.iter().enumerate() {
        let mesh = &scene.meshes[inst.mesh];
        let double = scene.material_of(mesh).double_sided;
        for f in mesh.facets() {
            assert_eq!(f.len, 3, "glTF triangles");
            let c: Vec<usize> = f.corners().collect();
            let p: Vec<Vec3> = c
                .iter()
                .map(|&k| {
                    inst.world
                        .transform_point3(mesh.positions[mesh.corners[k] as usize])
                })
                .collect();
            let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
            let n = e1.cross(e2);
            let facing = n.dot(dir);
            if facing.abs() < 1e-12 || (!double && facing > 0.0) {
                continue;
            }
            // Moeller-Trumbore.
            let q = dir.cross(e2);
            let det = e1.dot(q);
            let s = origin - p[0];
            let b1 = s.dot(q) / det;
            let r = s.cross(e1);
            let b2 = dir.dot(r) / det;
            let t = e2.dot(r) / det;
            if b1 < 0.0 || b2 < 0.0 || b1 + b2 > 1.0 || t <= 0.0 {
                continue;
            }
            if best.as_ref().is_some_and(|(bt, _)| *bt <= t) {
                continue;
            }
            let bary = [1.0 - b1 - b2, b1, b2];
            let uvs = mesh
                .uvs
                .iter()
                .map(|ch| {
                    (0..3)
                        .map(|k| ch.at(c[k], mesh.corners[c[k]]) * bary[k])
                        .sum()
                })
                .collect();
            best = Some((t, Hit { instance: i, uvs }));
        }
    }
    best.map(|(_, h)| h)
}

/// glTF's wrap of one coordinate onto [0, 1).
fn wrap(c: f32, mode: Wrap) -> f32 {
    match mode {
        Wrap::Repeat => c - c.floor(),
        Wrap::MirroredRepeat => {
            let m = c.rem_euclid(2.0);
            if m < 1.0 {
                m
            } else {
                2.0 - m
            }
        }
        Wrap::ClampToEdge => c.clamp(0.0, 1.0),
    }
}

/// The texel UV `uv` names under the wrap modes (S, T).
fn texel(t: &Texture, uv: Vec2, modes: (Wrap, Wrap)) -> Vec4 {
    let index = |c: f32, mode: Wrap, n: u32| ((wrap(c, mode) * n as f32) as u32).min(n - 1);
    t.fetch(
        index(uv.x, modes.0, t.width),
        index(uv.y, modes.1, t.height),
    )
}

/// The first hit of every pixel centre's ray, row by row.
fn cast_all(scene: &Scene, cam: &Camera, w: u32, h: u32) -> Vec<Option<Hit>> {
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let (o, d) = ray(cam, w, h, x as f32, y as f32);
            cast(scene, o, d)
        })
        .collect()
}

/// Pixel (x, y)'s hit if it and its four neighbours hit instance `inst` (not on an outline).
fn interior(hits: &[Option<Hit>], w: u32, h: u32, x: u32, y: u32, inst: usize) -> Option<&Hit> {
    if x == 0 || y == 0 || x + 1 >= w || y + 1 >= h {
        return None;
    }
    let at = |x: u32, y: u32| hits[(y * w + x) as usize].as_ref();
    let same = |x, y| at(x, y).is_some_and(|hit: &Hit| hit.instance == inst);
    (same(x, y) && same(x - 1, y) && same(x + 1, y) && same(x, y - 1) && same(x, y + 1))
        .then(|| at(x, y))
        .flatten()
}

/// Linear colour distance for "the same" texel (8-bit sRGB texels decoded exactly, times a
/// tint in f32).
const SAME: f32 = 0.02;

/// Counts of a pixel comparison: compared pixels and those that matched.
#[derive(Debug, Default)]
struct Tally {
    compared: usize,
    matched: usize,
}

impl Tally {
    fn add(&mut self, got: Vec4, want: Vec4) {
        self.compared += 1;
        let d = (got.min(Vec4::ONE) - want.min(Vec4::ONE))
            .truncate()
            .abs()
            .max_element();
        self.matched += usize::from(d < SAME);
    }
    fn fraction(&self) -> f64 {
        self.matched as f64 / self.compared.max(1) as f64
    }
}

/// Compares the interior pixels of instance `inst` with `predict`, and, where `wrong` (a
/// plausible misreading) predicts something else, with `wrong`: (right, wrong).
fn compare(
    image: &Framebuffer,
    hits: &[Option<Hit>],
    inst: usize,
    predict: impl Fn(&Hit) -> Vec4,
    wrong: impl Fn(&Hit) -> Vec4,
) -> (Tally, Tally) {
    let (w, h) = (image.width, image.height);
    let (mut right, mut misread) = (Tally::default(), Tally::default());
    for y in 0..h {
        for x in 0..w {
            let Some(hit) = interior(hits, w, h, x, y, inst) else {
                continue;
            };
            let got = image.pixel(x, y);
            let want = predict(hit);
            right.add(got, want);
            let other = wrong(hit);
            if (other.min(Vec4::ONE) - want.min(Vec4::ONE))
                .abs()
                .max_element()
                > 0.2
            {
                misread.add(got, other);
            }
        }
    }
    (right, misread)
}

fn is_red(c: Vec4) -> bool {
    // The crosses' red, sRGB (221, 44, 0): linear (0.72, 0.025, 0).
    c.x > 0.3 && c.y < 0.12 && c.z < 0.12
}

fn is_green(c: Vec4) -> bool {
    // The ticks' green, sRGB (0, 200, 0): linear (0, 0.58, 0).
    c.y > 0.3 && c.x < 0.12 && c.z < 0.12
}

/// An orthographic camera looking along +z at `centre` (from z = -20), half height `half`.
fn facing(centre: Vec3, half: f32) -> Camera {
    Camera {
        eye: Vec3::new(centre.x, centre.y, -20.0),
        target: Vec3::new(centre.x, centre.y, 0.0),
        up: Vec3::Y,
        ortho: Some(half),
        near: 0.1,
        far: 100.0,
        ..Camera::default()
    }
}

/// World bounds of instance `inst`.
fn instance_bounds(scene: &Scene, inst: usize) -> (Vec3, Vec3) {
    let i = &scene.instances[inst];
    scene.meshes[i.mesh]
        .positions
        .iter()
        .map(|&p| i.world.transform_point3(p))
        .fold((Vec3::MAX, Vec3::MIN), |(lo, hi), p| (lo.min(p), hi.max(p)))
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn texture_coordinate_test_squares_are_upright_and_in_their_corners() {
    let scene = khronos("TextureCoordinateTest");
    let scene = nearest(scene);
    // The squares lie in z = 0 facing -z (their normals), the grey plane behind at z =
    // 0.05. Looking along +z from -z, the view's right is world -x: the "TopLeft" square
    // (x, y in [0.2, 1.2]) is seen at the top left, as its name says.
    let whole = facing(Vec3::ZERO, 1.3);
    let vp = whole.projection(1.0) * whole.view();
    let texture = scene.textures[0].clone();
    let modes = (Wrap::Repeat, Wrap::Repeat);
    for (name, left, top) in [
        ("TopLeftNode", true, true),
        ("TopRightNode", false, true),
        ("BottomLeftNode", true, false),
        ("BottomRightNode", false, false),
    ] {
        let inst = scene
            .instances
            .iter()
            .position(|i| i.name == name)
            .unwrap_or_else(|| panic!("no node {name}"));
        let mesh = &scene.meshes[scene.instances[inst].mesh];
        let tint = scene.materials[mesh.material.unwrap()].base_color;
        let (lo, hi) = instance_bounds(&scene, inst);
        // Where the square is in the whole view (NDC: x right, y up).
        let c = vp.project_point3(0.5 * (lo + hi));
        assert_eq!((c.x < 0.0, c.y > 0.0), (left, top), "{name} is at {c}");
        // The square's corner with the smallest UV is its region's upper left in the
        // texture: upright means it is drawn at the square's upper left on screen.
        let world = scene.instances[inst].world;
        let corners: Vec<(Vec2, Vec2)> = mesh
            .corners
            .iter()
            .enumerate()
            .map(|(c, &v)| {
                let p = vp.project_point3(world.transform_point3(mesh.positions[v as usize]));
                (mesh.uvs[0].at(c, v), p.truncate())
            })
            .collect();
        let (uv_lo, s_lo) = *corners
            .iter()
            .min_by(|a, b| (a.0.x + a.0.y).total_cmp(&(b.0.x + b.0.y)))
            .unwrap();
        for (_, s) in &corners {
            assert!(
                s.x >= s_lo.x - 1e-4 && s.y <= s_lo.y + 1e-4,
                "{name}: UV {uv_lo} is not at the upper left on screen ({s_lo} vs {s})"
            );
        }
        // Pixel by pixel, zoomed onto the square (magnified: 330 pixels for 205 texels):
        // the texel its UV names, tinted; and not the upside-down reading (v mirrored
        // within the square's range).
        let (v_lo, v_hi) = corners.iter().fold((f32::MAX, f32::MIN), |(a, b), c| {
            (a.min(c.0.y), b.max(c.0.y))
        });
        let cam = facing(0.5 * (lo + hi), 0.6);
        let (w, h) = (400, 400);
        let image = draw(&scene, &cam, w, h);
        let hits = cast_all(&scene, &cam, w, h);
        let (right, flipped) = compare(
            &image,
            &hits,
            inst,
            |hit| texel(&texture, hit.uvs[0], modes) * tint,
            |hit| {
                let uv = hit.uvs[0];
                texel(&texture, Vec2::new(uv.x, v_lo + v_hi - uv.y), modes) * tint
            },
        );
        eprintln!(
            "{name}: {:.4} of {} pixels as predicted; upside down {:.4} of {} where it differs",
            right.fraction(),
            right.compared,
            flipped.fraction(),
            flipped.compared
        );
        assert!(right.compared > 50_000, "{name}: {right:?}");
        assert!(right.fraction() > 0.99, "{name}: {right:?}");
        assert!(flipped.compared > 1000, "{name}: {flipped:?}");
        assert!(
            flipped.fraction() < 0.2,
            "{name}: upside down matches: {flipped:?}"
        );
    }
}

/// The wrap modes (S = u, T = v) of each textured mesh, from the sampler names the file
/// gives its textures (e.g. `RepeatSMirrorTSampler` on `TextureMirrorTextureT`).
const SETTINGS_WRAPS: [(&str, Wrap, Wrap); 8] = [
    ("TextureMirrorMeshT", Wrap::Repeat, Wrap::MirroredRepeat),
    ("TextureMirrorMeshS", Wrap::MirroredRepeat, Wrap::Repeat),
    ("TextureRepeatMeshT", Wrap::ClampToEdge, Wrap::Repeat),
    ("TextureClampMeshT", Wrap::Repeat, Wrap::ClampToEdge),
    ("TextureRepeatMeshS", Wrap::Repeat, Wrap::ClampToEdge),
    ("TextureClampMeshS", Wrap::ClampToEdge, Wrap::Repeat),
    ("DoubleSidedMesh", Wrap::Repeat, Wrap::Repeat),
    ("SingleSidedMesh", Wrap::Repeat, Wrap::Repeat),
];

/// A plausible wrong wrap mode instead of `mode`.
fn misread(mode: Wrap) -> Wrap {
    match mode {
        Wrap::Repeat => Wrap::ClampToEdge,
        Wrap::MirroredRepeat | Wrap::ClampToEdge => Wrap::Repeat,
    }
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn texture_settings_test_shows_ticks_and_never_the_red_cross() {
    let scene = khronos("TextureSettingsTest");
    // The root node maps the file's (x, y, z) to (-x, z, y): the rows lie in the plane
    // z = 0 facing -z (normals -y in the file), one above the other along y, the labels
    // beside them and the blue background behind (z = 0.1 to 0.15). Looking along +z
    // from -z frames them all.
    let (lo, hi) = scene.bounds().unwrap();
    let whole = facing(0.5 * (lo + hi), 0.55 * (hi.y - lo.y));
    let (w, h) = (600, 600);
    let image = draw(&scene, &whole, w, h);
    let red = image.color.iter().filter(|&&c| is_red(c)).count();
    assert_eq!(red, 0, "{red} pixels show the red cross");

    let sharp = nearest(scene.clone());
    for (name, s, t) in SETTINGS_WRAPS {
        let mesh_index = scene
            .meshes
            .iter()
            .position(|m| m.name == name)
            .unwrap_or_else(|| panic!("no mesh {name}"));
        let inst = scene
            .instances
            .iter()
            .position(|i| i.mesh == mesh_index)
            .unwrap();
        let mesh = &scene.meshes[mesh_index];
        let slot = scene.materials[mesh.material.unwrap()]
            .base_color_texture
            .unwrap();
        // The loader read the sampler the file gives this texture.
        assert_eq!(
            (slot.sampler.wrap_u, slot.sampler.wrap_v),
            (s, t),
            "{name}: the sampler's wrap modes"
        );
        let texture = scene.textures[slot.texture].clone();
        // Zoomed onto the row (3.05 x 0.9 units; each of its squares, 0.9 units, shows
        // about 130 x 130 texels on about 190 x 190 pixels).
        let (blo, bhi) = instance_bounds(&scene, inst);
        let (w, h) = (720, 320);
        let half = 0.55 * (bhi.y - blo.y).max((bhi.x - blo.x) * h as f32 / w as f32);
        let cam = facing(0.5 * (blo + bhi), half);
        let green = draw(&scene, &cam, w, h)
            .color
            .iter()
            .filter(|&&c| is_green(c))
            .count();
        let image = draw(&sharp, &cam, w, h);
        let hits = cast_all(&sharp, &cam, w, h);
        let (right, misreading) = compare(
            &image,
            &hits,
            inst,
            |hit| texel(&texture, hit.uvs[0], (s, t)),
            |hit| texel(&texture, hit.uvs[0], (misread(s), misread(t))),
        );
        eprintln!(
            "{name}: {:.4} of {} pixels as predicted, {green} green; misread wrap: \
             {:.4} of {} where it differs",
            right.fraction(),
            right.compared,
            misreading.fraction(),
            misreading.compared
        );
        assert!(right.compared > 10_000, "{name}: {right:?}");
        assert!(right.fraction() > 0.98, "{name}: {right:?}");
        assert!(
            green > 1000,
            "{name}: the tick shows ({green} green pixels)"
        );
        if !name.ends_with("SidedMesh") {
            // The wrap mode matters here: another one would show something else.
            assert!(misreading.compared > 1000, "{name}: {misreading:?}");
            assert!(misreading.fraction() < 0.2, "{name}: {misreading:?}");
        }
    }

    // Teeth: with every sampler set to repeat, the crosses appear.
    let mut wrong = scene.clone();
    for m in &mut wrong.materials {
        if let Some(slot) = &mut m.base_color_texture {
            slot.sampler.wrap_u = Wrap::Repeat;
            slot.sampler.wrap_v = Wrap::Repeat;
        }
    }
    let bad = draw(&wrong, &whole, w, h);
    let red = bad.color.iter().filter(|&&c| is_red(c)).count();
    assert!(
        red > 500,
        "repeat everywhere shows the crosses: {red} red pixels"
    );
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn multi_uv_test_reads_the_emissive_map_through_the_second_set() {
    let scene = khronos("MultiUVTest");
    let scene = nearest(scene);
    let mesh = &scene.meshes[0];
    assert_eq!(mesh.uvs.len(), 2, "TEXCOORD_0 and TEXCOORD_1");
    let material = scene.materials[0].clone();
    let base = material.base_color_texture.expect("base colour texture");
    let glow = material.emissive_texture.expect("emissive texture");
    assert_eq!((base.uv_set, glow.uv_set), (0, 1));
    let (base_t, glow_t): (Arc<Texture>, Arc<Texture>) = (
        scene.textures[base.texture].clone(),
        scene.textures[glow.texture].clone(),
    );
    // The file's own camera looks at three faces of the cube.
    let cam = scene.cameras.first().expect("the file's camera").clone();
    let (w, h) = (640, 480);
    let image = draw(&scene, &cam, w, h);
    let hits = cast_all(&scene, &cam, w, h);
    let modes = (Wrap::Repeat, Wrap::Repeat);
    let lit = |hit: &Hit, emissive_set: usize| {
        let b = texel(&base_t, hit.uvs[0], modes) * material.base_color;
        let e = texel(&glow_t, hit.uvs[emissive_set], modes).truncate() * material.emissive;
        b + e.extend(0.0)
    };
    let (right, set0) = compare(&image, &hits, 0, |hit| lit(hit, 1), |hit| lit(hit, 0));
    eprintln!(
        "MultiUVTest: {:.4} of {} pixels as predicted; emissive through TEXCOORD_0: {:.4} of \
         {} where it differs",
        right.fraction(),
        right.compared,
        set0.fraction(),
        set0.compared
    );
    assert!(right.compared > 20_000, "{right:?}");
    assert!(right.fraction() > 0.98, "{right:?}");
    assert!(
        set0.compared > 1000,
        "the two readings differ on {} pixels",
        set0.compared
    );
    assert!(set0.fraction() < 0.1, "{set0:?}");
}
