//! realist against three.js r187 on the same view: the references in `tests/threejs/refs/`
//! are rendered by three.js in headless Chromium (`bash tests/threejs/make-refs.sh`; the
//! script and its pinned packages are in that folder), so this test needs neither.
//!
//! `models/pbr/no-material.glb` is a unit sphere without a material: the specification's
//! default, white, metallic 1, roughness 1, which three's GLTFLoader also applies. Under a
//! 1-lux directional light from the camera, without tone mapping, both renderers draw the
//! glTF BRDF and give the punctual light back the energy single scattering loses between
//! microfacets, by the same formula (each specular lobe times `1 + F0 (1/E_ss - 1)`), with
//! `E_ss` read at the same table coordinates (three.js's 16 x 16 table at texel centres:
//! roughness 1 compensates as 0.969 does, 1/0.345 head-on instead of the exact 1/0.307;
//! with the exact value realist's centre was 139 against three's 132, mean 4.4 levels).

use std::path::Path;

use glam::{DVec3, Vec3, Vec4};
use realist::load::{self, LoadOptions};
use realist::raster::Framebuffer;
use realist::render::{
    probe, Environment, Lights, PreparedScene, Renderer, Settings, ToneMap, View,
};
use realist::scene::{Camera, Light, Scene};

const SIZE: u32 = 256;

fn reference(name: &str) -> image::RgbImage {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/threejs/refs")
        .join(name);
    image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .into_rgb8()
}

/// realist's render of `model` from (0, 0, 3) towards the origin (45 degrees), lit by a
/// 1-lux directional light travelling along -Z, no environment, no tone map, black
/// background, as 8-bit sRGB.
fn render(model: &str, single_scatter: bool) -> image::RgbImage {
    let scene = load_model(model);
    rgb8(&frame(scene, single_scatter, 3.0, 1.0, 0.0))
}

fn load_model(model: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(model);
    load::load(&path, &LoadOptions::default()).expect("model loads")
}

/// The camera from (0, 0, `distance`) towards the origin, 45 degrees.
fn view(distance: f32) -> View {
    View {
        camera: Camera {
            eye: Vec3::new(0.0, 0.0, distance),
            target: Vec3::ZERO,
            up: Vec3::Y,
            yfov: 45f32.to_radians(),
            near: 0.5,
            far: 10.0,
            ..Camera::default()
        },
        width: SIZE,
        height: SIZE,
    }
}

/// The lights: a directional light of `lux` travelling along -Z (none at 0) and a uniform
/// surround of radiance `surround` (the ambient light, which the `pbr` mode reflects as a
/// uniform environment); no environment, no tone map, black background.
fn settings(single_scatter: bool, lux: f32, surround: f32) -> Settings {
    let mut lights = Vec::new();
    if lux > 0.0 {
        lights.push(Light::directional(Vec3::NEG_Z, Vec3::splat(lux)));
    }
    if surround > 0.0 {
        lights.push(Light::ambient(Vec3::splat(surround)));
    }
    Settings {
        lights: Lights::Custom {
            lights,
            follow_camera: false,
        },
        environment: Environment::Off,
        tone: ToneMap::Clamp,
        background: Vec4::new(0.0, 0.0, 0.0, 1.0),
        single_scatter,
        ..Settings::default()
    }
}

/// realist's linear frame of `scene` seen from (0, 0, `distance`) under [`settings`].
fn frame(
    scene: Scene,
    single_scatter: bool,
    distance: f32,
    lux: f32,
    surround: f32,
) -> Framebuffer {
    let prepared = PreparedScene::new(scene);
    let mut r = Renderer::new();
    r.render(
        &prepared,
        &settings(single_scatter, lux, surround),
        &view(distance),
    );
    r.take_target().expect("a frame").resolve()
}

/// A linear frame as 8-bit sRGB.
fn rgb8(fb: &Framebuffer) -> image::RgbImage {
    let enc = realist::color::srgb8;
    image::RgbImage::from_fn(fb.width, fb.height, |x, y| {
        let c = fb.color[(y * fb.width + x) as usize];
        image::Rgb([enc(c.x), enc(c.y), enc(c.z)])
    })
}

/// Per-pixel largest channel difference over the pixels both images cover with two pixels
/// of margin (the silhouettes' anti-aliasing aside): (mean, max, pixels compared).
fn compare(a: &image::RgbImage, b: &image::RgbImage) -> (f64, u8, usize) {
    let (mut sum, mut max, mut n) = (0u64, 0u8, 0usize);
    for y in 0..a.height() {
        for x in 0..a.width() {
            if !inside(a, x, y) || !inside(b, x, y) {
                continue;
            }
            let (p, q) = (a.get_pixel(x, y).0, b.get_pixel(x, y).0);
            let d = (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap_or(0);
            sum += u64::from(d);
            max = max.max(d);
            n += 1;
        }
    }
    (sum as f64 / n.max(1) as f64, max, n)
}

#[test]
fn the_default_material_under_a_head_on_light_against_three_js() {
    let three = reference("no-material-headon.png");
    // three.js's centre: the single-scattering lobe head-on, 1/(4π) = 0.0796, times its
    // compensation 1/0.3453: 0.2305, sRGB 132.
    assert_eq!(three.get_pixel(128, 128).0, [132, 132, 132]);
    let ours = render("models/pbr/no-material.glb", false);
    let (mean, max, n) = compare(&ours, &three);
    eprintln!("realist vs three.js r187, default material: mean {mean:.2}, max {max} levels over {n} pixels");
    assert!(n > 30_000, "the sphere covers both images: {n} pixels");
    // The same centre: the lobe times 1/E_ss at three's coordinates.
    assert_eq!(ours.get_pixel(128, 128).0, [132, 132, 132]);
    // The bound is 4 levels; measured: mean 0.03, max 1.
    assert!(mean < 0.5 && max <= 4, "mean {mean:.2}, max {max}");
    // Without the compensation (the specification's single-scattering BRDF) the sphere is
    // far darker than three's: what the compensation fixed.
    let single = render("models/pbr/no-material.glb", true);
    let (mean_ss, _, _) = compare(&single, &three);
    eprintln!("single scattering only: mean {mean_ss:.2} levels");
    assert_eq!(
        single.get_pixel(128, 128).0[0],
        realist::color::srgb8(0.25 / std::f32::consts::PI)
    );
    assert!(mean_ss > 30.0, "{mean_ss}");
}

/// The layered spheres are seen from (0, 0, 1.5) under a 1-lux light travelling along -Z and
/// a uniform surround of radiance 0.25 (three's PMREM of a uniform background).
const LAYER_DISTANCE: f32 = 1.5;
const SURROUND: f32 = 0.25;

/// Whether the 5 x 5 pixels around (x, y) are all covered (not the black background): the
/// pixels [`compare`] counts, the silhouette's anti-aliasing aside.
fn inside(img: &image::RgbImage, x: u32, y: u32) -> bool {
    (-2i64..=2).all(|d| {
        (-2i64..=2).all(|e| {
            let (u, v) = (i64::from(x) + d, i64::from(y) + e);
            (0..i64::from(img.width())).contains(&u)
                && (0..i64::from(img.height())).contains(&v)
                && img.get_pixel(u as u32, v as u32).0 != [0, 0, 0]
        })
    })
}

/// Largest channel difference of two 8-bit colours.
fn levels(a: [u8; 3], b: [u8; 3]) -> u8 {
    (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap_or(0)
}

/// Linear RGB as 8-bit sRGB.
fn srgb(c: DVec3) -> [u8; 3] {
    let enc = realist::color::srgb8;
    [enc(c.x as f32), enc(c.y as f32), enc(c.z as f32)]
}

/// Below this N·V the clear coat's reflection of the surround differs from three's by more
/// than 4 levels (three's weight for it, see the test).
const GRAZING: f64 = 0.3;

#[test]
fn a_clear_coat_against_three_js() {
    let three = reference("clearcoat-headon.png");
    let scene = load_model("models/pbr/clearcoat.glb");
    let fb = frame(scene.clone(), false, LAYER_DISTANCE, 1.0, SURROUND);
    let ours = rgb8(&fb);
    let (mean, max, n) = compare(&ours, &three);
    eprintln!(
        "realist vs three.js r187, clear coat: mean {mean:.2}, max {max} levels over {n} pixels"
    );
    assert!(n > 20_000, "the sphere covers both images: {n} pixels");
    // Outside the coat's highlight (more than 12 pixels from the centre), by how grazing
    // the view is.
    let prepared = PreparedScene::new(scene.clone());
    let settings = settings(false, 1.0, SURROUND);
    let eye = DVec3::new(0.0, 0.0, f64::from(LAYER_DISTANCE));
    // The coat's reflection of the surround: the specification weights the coat's lobe by
    // clearcoat Fr(N·V), realist's `Fr(N·V) (A + B)` times the prefiltered radiance; three
    // weights it by the coat's own split sum `0.04 A + B` (a Fresnel per microfacet), which
    // is less at grazing views (a coat over a base that reflects everything, in a uniform
    // surround: three's returns 90 % at N·V 0.2 and 74 % at 0.1, the specification's 97 %
    // and 93 %). And three draws every lobe rougher than the file says: it adds the
    // screen-space change of the normal per pixel ("geometryRoughness", its specular
    // anti-aliasing, lights_physical_fragment). At the centre of a sphere of radius 0.4 seen
    // from 1.1 away a pixel spans 2 · 1.1 · tan(22.5°) / 256 and turns the normal by that
    // over 0.4 (`g`); towards the silhouette it grows as 1 / N·V. Away from the highlight,
    // three's image is realist's with three's weight and roughness.
    let lut = realist::texture::env::brdf_lut();
    let g = 2.0 * 1.1 * libm::tan((22.5f64).to_radians()) / f64::from(SIZE) / 0.4;
    let (mut facing, mut grazing, mut predicted) = (0u8, (0u8, 1.0f64), 0u8);
    for (x, y, p) in ours.enumerate_pixels() {
        let (dx, dy) = (f64::from(x) - 127.5, f64::from(y) - 127.5);
        if libm::hypot(dx, dy) <= 12.0 || !inside(&ours, x, y) || !inside(&three, x, y) {
            continue;
        }
        let q = three.get_pixel(x, y).0;
        let d = levels(p.0, q);
        let Some(hit) = probe(&prepared, &settings, &view(LAYER_DISTANCE), x, y) else {
            continue;
        };
        let nv = hit
            .normal
            .as_dvec3()
            .dot((eye - hit.position.as_dvec3()).normalize());
        let (a, b) = lut.lookup(nv as f32, 0.3);
        let (a, b) = (f64::from(a), f64::from(b));
        let (ta, tb) = lut.lookup(nv as f32, (0.3 + g / nv.max(0.05)) as f32);
        let (ta, tb) = (f64::from(ta), f64::from(tb));
        let fr = 0.04 + 0.96 * (1.0 - nv).powi(5);
        let linear = fb.color[(y * SIZE + x) as usize].truncate().as_dvec3();
        let three_like =
            linear + DVec3::splat(f64::from(SURROUND) * (0.04 * ta + tb - fr * (a + b)));
        predicted = predicted.max(levels(srgb(three_like), q));
        if nv > GRAZING {
            facing = facing.max(d);
        } else if d > grazing.0 {
            grazing = (d, nv);
        }
    }
    eprintln!(
        "outside the highlight: max {facing} levels where N·V > {GRAZING}, {} at N·V {:.3}; with three's weight for the surround max {predicted}",
        grazing.0, grazing.1
    );
    assert!(facing <= 4, "{facing}");
    assert!(predicted <= 4, "{predicted}");
    // In the highlight: with the coat `g` rougher, realist's centre is three's.
    let mut rough = scene;
    rough.materials[0].pbr.as_mut().unwrap().clearcoat_roughness += g as f32;
    let like_three = rgb8(&frame(rough, false, LAYER_DISTANCE, 1.0, SURROUND));
    let (ours_c, three_c, like_c) = (
        ours.get_pixel(128, 128).0,
        three.get_pixel(128, 128).0,
        like_three.get_pixel(128, 128).0,
    );
    eprintln!("centre: realist {ours_c:?}, with three's roughness (+{g:.4}) {like_c:?}, three {three_c:?}");
    let mut centre = 0u8;
    for y in 124..=132 {
        for x in 124..=132 {
            centre = centre.max(levels(
                like_three.get_pixel(x, y).0,
                three.get_pixel(x, y).0,
            ));
        }
    }
    assert!(
        centre <= 2,
        "the highlight with three's roughness: {centre} levels"
    );
    assert!(mean < 1.0, "mean {mean:.2}");
}

/// KHR_materials_sheen's Charlie distribution at `N·H` (α = roughness²), without the floor
/// three puts under sin²θ_h (it matters only where the sheen is negligible).
fn charlie_d(nh: f64, roughness: f64) -> f64 {
    let a = roughness * roughness;
    (2.0 + 1.0 / a) * libm::pow((1.0 - nh * nh).max(0.0), 0.5 / a) / (2.0 * std::f64::consts::PI)
}

#[test]
fn a_sheen_against_three_js() {
    // three.js documents two approximations of its own for the sheen (in
    // lights_physical_pars_fragment): Neubelt and Pettineo's visibility `1 / (4 (NL + NV -
    // NL NV))` for the light's lobe instead of the specification's Charlie visibility, and a
    // curve fit of the layer's albedo (IBLSheenBRDF) instead of its integral (realist's
    // table, `tests/layers.rs`), for the surround's sheen and the scaling of the base. At
    // grazing views these differ by up to 9 levels here. So: where the view is within 35°
    // of the normal the two agree within 4 levels; everywhere, three's image is what its
    // formulas make of realist's own base (the same sphere without the sheen, lit by the
    // light and by the surround separately) within 4 levels.
    let three = reference("sheen-headon.png");
    let scene = load_model("models/pbr/sheen.glb");
    let ours = rgb8(&frame(scene.clone(), false, LAYER_DISTANCE, 1.0, SURROUND));
    let (mean, max, n) = compare(&ours, &three);
    eprintln!("realist vs three.js r187, sheen: mean {mean:.2}, max {max} levels over {n} pixels");
    assert!(n > 20_000, "the sphere covers both images: {n} pixels");
    let mut bare = scene.clone();
    bare.materials[0].pbr.as_mut().unwrap().sheen_color = Vec3::ZERO;
    let by_light = frame(bare.clone(), false, LAYER_DISTANCE, 1.0, 0.0);
    let by_surround = frame(bare, false, LAYER_DISTANCE, 0.0, SURROUND);
    let prepared = PreparedScene::new(scene);
    let (eye, l) = (DVec3::new(0.0, 0.0, f64::from(LAYER_DISTANCE)), DVec3::Z);
    let (color, max3, r) = (DVec3::new(1.0, 0.5, 0.25), 1.0, 0.5);
    // three's IBLSheenBRDF (its curve fit of the albedo).
    let fit = |nv: f64| {
        let (r2, inv) = (r * r, 1.0 / (r + 0.1));
        let a = -1.9362 + 1.0678 * r + 0.4573 * r2 - 0.8469 * inv;
        let b = -0.6014 + 0.5538 * r - 0.4670 * r2 - 0.1255 * inv;
        libm::exp(a * nv + b).clamp(0.0, 1.0)
    };
    let settings = settings(false, 1.0, SURROUND);
    let (mut near_normal, mut predicted, mut count) = (0u8, 0u8, 0);
    for y in (0..SIZE).step_by(3) {
        for x in (0..SIZE).step_by(3) {
            let q = three.get_pixel(x, y).0;
            let Some(p) = probe(&prepared, &settings, &view(LAYER_DISTANCE), x, y) else {
                continue;
            };
            if !inside(&three, x, y) || !inside(&ours, x, y) {
                continue;
            }
            let (nrm, pos) = (p.normal.as_dvec3(), p.position.as_dvec3());
            let v = (eye - pos).normalize();
            let (nv, nl) = (nrm.dot(v).max(1e-4), nrm.dot(l).max(0.0));
            let nh = nrm.dot((l + v).normalize()).max(0.0);
            let k = (y * SIZE + x) as usize;
            let (bl, bs) = (
                by_light.color[k].truncate().as_dvec3(),
                by_surround.color[k].truncate().as_dvec3(),
            );
            let neubelt = (1.0 / (4.0 * (nl + nv - nl * nv))).clamp(0.0, 1.0);
            let three_like = bl * (1.0 - max3 * fit(nv).max(fit(nl)))
                + bs * (1.0 - max3 * fit(nv))
                + color * (nl * charlie_d(nh, r) * neubelt)
                + color * (f64::from(SURROUND) * fit(nv));
            predicted = predicted.max(levels(srgb(three_like), q));
            if nv > libm::cos(35f64.to_radians()) {
                near_normal = near_normal.max(levels(ours.get_pixel(x, y).0, q));
            }
            count += 1;
        }
    }
    eprintln!(
        "within 35° of the normal: max {near_normal} levels; three's formulas on realist's base: max {predicted} levels ({count} pixels)"
    );
    assert!(count > 2000, "{count}");
    assert!(near_normal <= 4, "{near_normal}");
    assert!(predicted <= 4, "{predicted}");
}

/// A camera at (0, 0, `distance`) looking at the origin with a vertical field of view of
/// `yfov` radians, `width` x `height` pixels.
fn view_of(distance: f32, yfov: f32, width: u32, height: u32) -> View {
    let mut v = view(distance);
    v.camera.yfov = yfov;
    v.camera.near = 0.2;
    (v.width, v.height) = (width, height);
    v
}

/// realist's 8-bit sRGB image of `scene` from `v` under a 1-lux light travelling along -Z
/// and the uniform surround.
fn headon(scene: Scene, v: &View) -> image::RgbImage {
    let prepared = PreparedScene::new(scene);
    let mut r = Renderer::new();
    r.render(&prepared, &settings(false, 1.0, SURROUND), v);
    rgb8(&r.take_target().expect("a frame").resolve())
}

#[test]
fn the_layers_textures_against_three_js() {
    // layer-textures.glb reads the clear coat's, the sheen's, KHR_materials_specular's and
    // the iridescence's factors through textures; layer-factors.glb has the products as
    // factors (tests/layers.rs: realist draws the two alike). three.js draws the two alike
    // too. Where the view is within 35° of the normal (the bound the sheen test above
    // found), realist's image of the textured file is three's within 4 levels once three's
    // extra roughness is added to realist's lobes (its specular anti-aliasing, see the
    // clear coat test), which widens the bright highlights of the coat, the specular and
    // the iridescent metal: as the file says, their flanks differ by up to 14 levels
    // (measured: 14, 1, 8 and 9 on the four spheres; with three's roughness 1 on each).
    let v = view_of(4.0, 2.0 * libm::atanf(0.125f32), 320, 80);
    let three = reference("layer-textures-headon.png");
    let (mean, max, n) = compare(&three, &reference("layer-factors-headon.png"));
    eprintln!(
        "three.js, textures against factors: mean {mean:.3}, max {max} levels over {n} pixels"
    );
    assert!(max <= 1 && n > 5000, "{max} {n}");
    let scene = load_model("models/pbr/layer-textures.glb");
    let ours = headon(scene.clone(), &v);
    let (mean, max, n) = compare(&ours, &three);
    eprintln!("realist vs three.js r187, layer textures: mean {mean:.2}, max {max} levels over {n} pixels");
    // three's extra roughness: the view-space normal's change over a pixel at the spheres'
    // fronts (3.6 from the eye; radius 0.4).
    let g = 2.0 * 3.6 * 0.125 / 80.0 / 0.4;
    let mut rough = scene.clone();
    for m in &mut rough.materials {
        m.roughness += g;
    }
    // The coat's roughness is its factor times the texel's G, 102 / 255 = 0.4.
    rough.materials[0].pbr.as_mut().unwrap().clearcoat_roughness += g / 0.4;
    let like_three = headon(rough, &v);
    let prepared = PreparedScene::new(scene);
    let settings = settings(false, 1.0, SURROUND);
    let eye = DVec3::new(0.0, 0.0, 4.0);
    let (mut as_is, mut rougher) = ([0u8; 4], [0u8; 4]);
    for (x, y, p) in ours.enumerate_pixels() {
        if !inside(&ours, x, y) || !inside(&three, x, y) {
            continue;
        }
        let Some(hit) = probe(&prepared, &settings, &v, x, y) else {
            continue;
        };
        let nv = hit
            .normal
            .as_dvec3()
            .dot((eye - hit.position.as_dvec3()).normalize());
        if nv <= libm::cos(35f64.to_radians()) {
            continue;
        }
        let (k, q) = (hit.instance.min(3), three.get_pixel(x, y).0);
        as_is[k] = as_is[k].max(levels(p.0, q));
        rougher[k] = rougher[k].max(levels(like_three.get_pixel(x, y).0, q));
    }
    eprintln!(
        "within 35° of the normal (coat, sheen, specular, iridescence): max {as_is:?} levels; with three's roughness (+{g:.4}) max {rougher:?}"
    );
    assert!(rougher.iter().all(|&w| w <= 4), "{rougher:?}");
}

#[test]
fn a_coat_normal_map_against_three_js() {
    // coat-normal.glb: a quad whose coat has a normal map tilting it 7.9° towards +X (the
    // base reflects nothing), with TANGENT +X, w = 1 (bitangent N × T = +Y, glTF's rule).
    // Both renderers put the coat's highlight in the same column (tests/layers.rs finds
    // realist's where the tilted normal mirrors the light). three.js r187 uses the mesh's
    // tangents only with a base normal map (WebGLPrograms.js: `vertexTangents` needs
    // `normalMap` or anisotropy); for the coat's map it takes the frame from the derivatives
    // of the UVs, whose bitangent follows +V: -Y here, as if w were -1. The texel's G (128:
    // +0.004) then tilts three's coat up where realist's tilts down, moving the highlight
    // by a pixel (up to 9 levels on its flank). With w = -1 realist draws three's image.
    let v = view_of(1.5, 0.9, 129, 129);
    let three = reference("coat-normal-headon.png");
    let scene = load_model("models/pbr/coat-normal.glb");
    let ours = headon(scene.clone(), &v);
    let (mean, max, n) = compare(&ours, &three);
    eprintln!("realist vs three.js r187, coat normal map: mean {mean:.2}, max {max} levels over {n} pixels");
    let brightest = |img: &image::RgbImage| {
        (0..129)
            .max_by_key(|&x| img.get_pixel(x, 64).0[0])
            .unwrap_or(0)
    };
    let (a, b) = (brightest(&ours), brightest(&three));
    eprintln!("the highlight's column: realist {a}, three {b}");
    assert!(a.abs_diff(b) <= 1, "{a} vs {b}");
    let mut flipped = scene;
    for t in &mut flipped.meshes[0]
        .tangents
        .as_mut()
        .expect("tangents")
        .values
    {
        t.w = -t.w;
    }
    let (mean_f, max_f, n_f) = compare(&headon(flipped, &v), &three);
    eprintln!("with three's bitangent: mean {mean_f:.2}, max {max_f} levels over {n_f} pixels");
    assert!(n_f > 6000, "{n_f}");
    assert!(max_f <= 4 && mean_f < 1.0, "{mean_f} {max_f}");
}

#[test]
fn iridescence_against_three_js() {
    // iridescence.glb: a film of IOR 1.8, 450 nm thick, on a black dielectric sphere. Both
    // renderers take the film's Fresnel once per pixel at N·V (the Khronos sample viewer's
    // and three's shortcut for the extension's V·H) and turn it back into an F0 for the
    // surround (three's Schlick_to_F0), so away from the highlight, where three's lobe is
    // rougher (see the clear coat test), they agree within 4 levels.
    let three = reference("iridescence-headon.png");
    let scene = load_model("models/pbr/iridescence.glb");
    let ours = rgb8(&frame(scene, false, LAYER_DISTANCE, 1.0, SURROUND));
    let (mean, max, n) = compare(&ours, &three);
    eprintln!(
        "realist vs three.js r187, iridescence: mean {mean:.2}, max {max} levels over {n} pixels"
    );
    let prepared = PreparedScene::new(load_model("models/pbr/iridescence.glb"));
    let settings = settings(false, 1.0, SURROUND);
    let eye = DVec3::new(0.0, 0.0, f64::from(LAYER_DISTANCE));
    let (mut facing, mut grazing) = (0u8, (0u8, 1.0f64));
    for (x, y, p) in ours.enumerate_pixels() {
        if !inside(&ours, x, y) || !inside(&three, x, y) {
            continue;
        }
        let Some(hit) = probe(&prepared, &settings, &view(LAYER_DISTANCE), x, y) else {
            continue;
        };
        let (n, v) = (
            hit.normal.as_dvec3(),
            (eye - hit.position.as_dvec3()).normalize(),
        );
        let d = levels(p.0, three.get_pixel(x, y).0);
        if n.dot((v + DVec3::Z).normalize()) > libm::cos(15f64.to_radians()) {
            continue;
        }
        if n.dot(v) > GRAZING {
            facing = facing.max(d);
        } else if d > grazing.0 {
            grazing = (d, n.dot(v));
        }
    }
    eprintln!(
        "outside the highlight: max {facing} levels where N·V > {GRAZING}, {} at N·V {:.3}",
        grazing.0, grazing.1
    );
    assert!(n > 20_000, "{n}");
    assert!(facing <= 4, "{facing}");
    // The rim (N·V < 0.3): three's lobe is rougher there by the normal's change per pixel,
    // which grows as 1 / N·V (0.0089 at the centre, so about 0.04 at N·V 0.235; see the
    // clear coat test). With that roughness added, realist's rim is three's within 4.
    let mut rough = load_model("models/pbr/iridescence.glb");
    rough.materials[0].roughness += 0.04;
    let rough = rgb8(&frame(rough, false, LAYER_DISTANCE, 1.0, SURROUND));
    let mut rim = 0u8;
    for (x, y, p) in rough.enumerate_pixels() {
        if !inside(&rough, x, y) || !inside(&three, x, y) {
            continue;
        }
        let Some(hit) = probe(&prepared, &settings, &view(LAYER_DISTANCE), x, y) else {
            continue;
        };
        let (n, v) = (
            hit.normal.as_dvec3(),
            (eye - hit.position.as_dvec3()).normalize(),
        );
        if n.dot(v) <= GRAZING {
            rim = rim.max(levels(p.0, three.get_pixel(x, y).0));
        }
    }
    eprintln!("the rim with three's roughness there (+0.04): max {rim} levels");
    assert!(rim <= 4, "{rim}");
}

#[test]
fn anisotropy_against_three_js() {
    // anisotropy.glb and anisotropy-texture.glb: a brushed metal quad whose highlight
    // stretches along 30° and 120° (tests/layers.rs checks it against the specification's
    // lobe), seen head-on from 1.2 away. Both renderers draw the specification's
    // anisotropic GGX for the light and read the surround about Filament's bent normal.
    let v = view_of(1.2, 1.4, 129, 129);
    for m in ["anisotropy", "anisotropy-texture"] {
        let three = reference(&format!("{m}-headon.png"));
        let ours = headon(load_model(&format!("models/pbr/{m}.glb")), &v);
        let (mean, max, n) = compare(&ours, &three);
        eprintln!(
            "realist vs three.js r187, {m}: mean {mean:.2}, max {max} levels over {n} pixels"
        );
        assert!(n > 12_000, "{n}");
        assert!(max <= 4, "{m}: {max}");
    }
}

#[test]
fn transmission_against_three_js() {
    // transmission.glb: a glass sphere (IOR 1.5, roughness 0.1, 0.8 thick, absorbing
    // towards orange, dispersion 2) in front of an opaque blue sphere, on a grey background
    // (0.3 in sRGB).
    // Both renderers refract the opaque frame as three.js draws transmission in a
    // rasterizer: the ray refracted into the surface leaves it after the thickness, where
    // the frame is read, blurred by the roughness, and Beer's law absorbs it.
    let three = reference("transmission-headon.png");
    let grey = realist::color::srgb_to_linear(0.3);
    let v = view_of(2.0, 45f32.to_radians(), SIZE, SIZE);
    let prepared = PreparedScene::new(load_model("models/pbr/transmission.glb"));
    let mut r = Renderer::new();
    let s = Settings {
        background: Vec4::new(grey, grey, grey, 1.0),
        ..settings(false, 1.0, SURROUND)
    };
    r.render(&prepared, &s, &v);
    let ours = rgb8(&r.take_target().expect("a frame").resolve());
    let (mean, max, n) = compare(&ours, &three);
    eprintln!(
        "realist vs three.js r187, transmission: mean {mean:.2}, max {max} levels over {n} pixels"
    );
    // On the glass, two pixels in from its silhouette; and the rest.
    // What each pixel shows: the glass (0), the blue sphere (1) or the background (2).
    let shown: Vec<usize> = (0..SIZE * SIZE)
        .map(|i| probe(&prepared, &s, &v, i % SIZE, i / SIZE).map_or(2, |h| h.instance.min(1)))
        .collect();
    let what = |x: i64, y: i64| {
        if !(0..i64::from(SIZE)).contains(&x) || !(0..i64::from(SIZE)).contains(&y) {
            return 3;
        }
        shown[(y * i64::from(SIZE) + x) as usize]
    };
    let (mut on_glass, mut elsewhere, mut count, mut over) = ((0u8, 0, 0), 0u8, 0, 0);
    for (x, y, p) in ours.enumerate_pixels() {
        let (xi, yi) = (i64::from(x), i64::from(y));
        let d = levels(p.0, three.get_pixel(x, y).0);
        let k = what(xi, yi);
        let same = (-2..=2).all(|dy| (-2..=2).all(|dx| what(xi + dx, yi + dy) == k));
        if !same {
            continue;
        }
        if k == 0 {
            // The light's highlight (roughness 0.1), where three's lobe is rougher (see
            // the clear coat test), aside.
            let hit = probe(&prepared, &s, &v, x, y).expect("the glass");
            let (n, to_eye) = (
                hit.normal.as_dvec3(),
                (DVec3::new(0.0, 0.0, 2.0) - hit.position.as_dvec3()).normalize(),
            );
            if n.dot((to_eye + DVec3::Z).normalize()) > libm::cos(15f64.to_radians()) {
                continue;
            }
            if d > 4 {
                over += 1;
            }
            if d > on_glass.0 {
                on_glass = (d, x, y);
            }
            count += 1;
        } else {
            elsewhere = elsewhere.max(d);
        }
    }
    eprintln!("on the glass ({count} pixels): max {on_glass:?} levels, {over} pixels over 4; elsewhere {elsewhere}");
    let on_glass = on_glass.0;
    // Along the refracted edge between the blue sphere and the background three's read
    // blurs more: it filters the frame with a B-spline bicubic kernel (which blurs even at
    // level 0) where realist reads it trilinearly (measured: 11 pixels above 4 levels, at
    // most 6).
    assert!(count > 10_000, "{count}");
    assert!(elsewhere <= 4, "{elsewhere}");
    assert!(on_glass <= 8 && over <= 20, "{on_glass} {over}");
}

#[test]
fn a_slab_and_dispersion_against_three_js() {
    // transmission-slab.glb (transmission 1, IOR 1, no Fresnel, 0.5 thick, absorbing) and
    // dispersion.glb (a slab of IOR 1.5 with dispersion 10 before a linear ramp), seen from
    // aside on a background of (0.6, 0.5, 0.4) in sRGB: tests/layers.rs checks both against
    // f64; three draws them alike, within 4 levels on the slab away from its edges.
    let bg = [0.6f32, 0.5, 0.4].map(realist::color::srgb_to_linear);
    let v = View {
        camera: Camera {
            eye: Vec3::new(1.2, 0.3, 2.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            yfov: 0.6,
            near: 0.5,
            far: 10.0,
            ..Camera::default()
        },
        width: 129,
        height: 129,
    };
    for m in ["transmission-slab", "dispersion"] {
        let three = reference(&format!("{m}-aside.png"));
        let scene = load_model(&format!("models/pbr/{m}.glb"));
        // The slab is the last instance.
        let slab = scene.instances.len() - 1;
        let prepared = PreparedScene::new(scene);
        let s = Settings {
            background: Vec4::new(bg[0], bg[1], bg[2], 1.0),
            ..settings(false, 1.0, SURROUND)
        };
        let mut r = Renderer::new();
        r.render(&prepared, &s, &v);
        let ours = rgb8(&r.take_target().expect("a frame").resolve());
        // The slab's pixels two in from its edges.
        let on = |x: i64, y: i64| {
            (0..129).contains(&x)
                && (0..129).contains(&y)
                && probe(&prepared, &s, &v, x as u32, y as u32).is_some_and(|h| h.instance == slab)
        };
        let (mut worst, mut n) = (0u8, 0);
        for (x, y, p) in ours.enumerate_pixels() {
            let (xi, yi) = (i64::from(x), i64::from(y));
            if (-2..=2).all(|dy| (-2..=2).all(|dx| on(xi + dx, yi + dy))) {
                worst = worst.max(levels(p.0, three.get_pixel(x, y).0));
                n += 1;
            }
        }
        eprintln!("realist vs three.js r187, {m}: max {worst} levels over {n} pixels of the slab");
        assert!(n > 2000, "{m}: {n}");
        assert!(worst <= 4, "{m}: {worst}");
    }
}
