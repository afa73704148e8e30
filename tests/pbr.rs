//! The `pbr` mode (glTF 2.0 metallic-roughness, the specification's Appendix B) on the test
//! files of `models/pbr/` (written by glTF-Transform, validated; see `models/README.md`):
//! the sphere grid against the f64 reference, the material extensions against their
//! formulas, and the white furnace.

mod common;

use std::f64::consts::PI;
use std::path::Path;
use std::sync::Arc;

use glam::{DVec3, Vec3, Vec4};
use realist::color::srgb_decode;
use realist::quality::{compare, general, LinearImage};
use realist::render::{render, Environment, Lights, PreparedScene, Settings, Shot};
use realist::scene::{Camera, Light, Scene};
use realist::shade::brdf;
use realist::shade::{PbrParams, Shading, Surface};
use realist::texture::env::{texel_dir, EnvImage, EnvView, Prefiltered};

/// Supersampling of the comparisons against the reference (4 x 4, as the issue asks).
const SS: u32 = 4;
/// Mean ΔE00 the sphere grid must stay under against the reference.
const GRID_MEAN_DE: f64 = 0.5;

fn model(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("models/pbr")
        .join(name);
    realist::load::load(&path, &realist::load::LoadOptions::default())
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// `lights` only (none: an empty list), black background, the mode the file asks for.
fn options(w: u32, h: u32, camera: Camera, lights: Vec<Light>) -> Shot {
    Shot {
        width: w,
        height: h,
        camera: Some(camera),
        settings: Settings {
            shading: None,
            background: Vec4::new(0.0, 0.0, 0.0, 1.0),
            lights: Lights::Custom {
                lights,
                follow_camera: false,
            },
            environment: Environment::Off,
            // The formulas of the specification, as they are: no tone map, and the lights'
            // single-scattering BRDF (the compensation is measured in tests/threejs.rs).
            tone: realist::render::ToneMap::Clamp,
            single_scatter: true,
            ..Settings::default()
        },
    }
}

/// The renderer's image at `SS` x the size, averaged down, in linear light.
fn rendered(scene: &Scene, opts: &Shot) -> LinearImage {
    let big = Shot {
        width: opts.width * SS,
        height: opts.height * SS,
        ..opts.clone()
    };
    let frame = render(&PreparedScene::new(scene.clone()), &big);
    LinearImage::from_framebuffer(&frame.image()).downsample(SS)
}

/// The grid seen from +Z (perspective: the reference has no orthographic camera).
fn grid_camera() -> Camera {
    Camera {
        eye: Vec3::new(0.0, 0.0, 7.0),
        target: Vec3::ZERO,
        near: 1.0,
        far: 20.0,
        ..Camera::default()
    }
}

/// The pixel of an `n` x `n` image from [`grid_camera`] where the centre of the sphere at
/// (x, y, 0) projects: the view is 2 · 7 tan 22.5° world units high at z = 0.
fn centre(n: u32, x: f32, y: f32) -> (u32, u32) {
    let k = 1.0 / (14.0 * libm::tanf(22.5f32.to_radians()));
    let p = |t: f32| ((0.5 + t * k) * n as f32) as u32;
    (p(x), n - 1 - p(y))
}

/// A white key light from the upper left, in front (1 lux: a white Lambert surface facing
/// it reflects 1/π), and a little ambient light (a uniform environment in `pbr`).
fn grid_lights() -> Vec<Light> {
    vec![
        Light::directional(Vec3::new(0.5, -0.6, -0.62).normalize(), Vec3::splat(3.0)),
        Light::ambient(Vec3::splat(0.1)),
    ]
}

#[test]
fn glb_materials_open_in_pbr_with_their_factors() {
    let scene = model("sphere-grid.glb");
    assert_eq!(scene.materials.len(), 25);
    for (k, m) in scene.materials.iter().enumerate() {
        let (i, j) = (k % 5, k / 5);
        assert!(m.pbr.is_some(), "a glTF material is metallic-roughness");
        assert_eq!(m.metallic, i as f32 / 4.0, "{}", m.name);
        assert_eq!(m.roughness, j as f32 / 4.0, "{}", m.name);
        assert!(
            (m.base_color - Vec4::new(0.9, 0.55, 0.2, 1.0))
                .abs()
                .max_element()
                < 1e-6
        );
    }
    // No mode forced: the frame is drawn in pbr (its metal column differs from Phong's).
    let opts = options(40, 40, grid_camera(), grid_lights());
    let auto = render(&PreparedScene::new(scene.clone()), &opts).image();
    let forced = Shot {
        settings: Settings {
            shading: Some(Shading::Pbr),
            ..opts.clone().settings
        },
        ..opts.clone()
    };
    let pbr = render(&PreparedScene::new(scene.clone()), &forced).image();
    assert_eq!(
        auto.color, pbr.color,
        "the default mode of a glTF file is pbr"
    );
}

/// The 5 x 5 metallic x roughness grid against the f64 reference, which evaluates the BRDF
/// (the same source, in f64) at every sample with exact visibility and normals; and it must
/// differ from Blinn-Phong by far more than that.
#[test]
fn sphere_grid_matches_the_f64_reference_under_a_directional_light() {
    let scene = model("sphere-grid.glb");
    let opts = options(120, 120, grid_camera(), grid_lights());
    let ras = rendered(&scene, &opts);
    let reference = general::reference(&scene, &opts, SS, true).expect("reference");
    let same = compare(&ras, &reference, 1.0);
    let blinn = Shot {
        settings: Settings {
            shading: Some(Shading::Blinn),
            ..opts.clone().settings
        },
        ..opts.clone()
    };
    let other = compare(&rendered(&scene, &blinn), &reference, 1.0);
    eprintln!(
        "sphere grid: mean ΔE00 {:.3} (p95 {:.3}) against the reference; Blinn-Phong {:.2}",
        same.mean_de2000, same.p95_de2000, other.mean_de2000
    );
    assert!(
        same.mean_de2000 < GRID_MEAN_DE,
        "mean ΔE00 {}",
        same.mean_de2000
    );
    assert!(
        other.mean_de2000 > 4.0 * GRID_MEAN_DE,
        "{}",
        other.mean_de2000
    );
}

/// A smooth high-dynamic-range environment made here (radiance 0.05 to about 9): a
/// horizon-to-zenith sky, a dark ground and a broad warm light (a cos⁸ lobe, about 35°
/// wide) up and to the left. Smooth, so what is measured is the split sum and not how a
/// small sun aliases.
fn hdr_environment() -> EnvView {
    let (w, h) = (256u32, 128u32);
    let key = Vec3::new(-0.5, 0.6, 0.62).normalize();
    let texels = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let d = texel_dir(x as usize, y as usize, w as usize, h as usize);
            let up = d.y.max(0.0);
            let sky = Vec3::new(0.3, 0.45, 0.8) * (0.4 + 0.6 * up) + Vec3::splat(0.05);
            let ground = Vec3::new(0.12, 0.1, 0.08) * (1.0 - up);
            let lobe = Vec3::new(9.0, 7.0, 5.0) * d.dot(key).max(0.0).powi(8);
            let c = if d.y >= 0.0 { sky } else { ground } + lobe;
            c.to_array()
        })
        .collect();
    let image = EnvImage::from_rgb(w, h, texels).expect("environment");
    EnvView::new(Arc::new(Prefiltered::build(image)))
}

/// The grid lit by `env` alone against the reference integrating the environment
/// directly (`general::reference`: GGX and cosine samples over the full-resolution image,
/// no prefiltering, table or SH): the mean ΔE00 and the 95th percentile.
fn grid_under(env: EnvView) -> (f64, f64) {
    let scene = model("sphere-grid.glb");
    let opts = Shot {
        settings: Settings {
            environment: Environment::On(env),
            ..options(120, 120, grid_camera(), vec![]).settings
        },
        ..options(120, 120, grid_camera(), vec![])
    };
    let ras = rendered(&scene, &opts);
    let reference = general::reference(&scene, &opts, SS, true).expect("reference");
    let m = compare(&ras, &reference, 1.0);
    if std::env::var("DIAG").is_ok() {
        for j in 0..5 {
            let mut row = String::new();
            for i in 0..5 {
                let mut acc = [0.0f64; 6];
                for (dx, dy) in [
                    (-6i32, 0i32),
                    (6, 0),
                    (0, -6),
                    (0, 6),
                    (0, 0),
                    (-4, -4),
                    (4, 4),
                ] {
                    let (x, y) = centre(120, i as f32 - 2.0, 2.0 - j as f32);
                    let o = ((y as i32 + dy) * 120 + x as i32 + dx) as usize;
                    for c in 0..3 {
                        acc[c] += ras.rgb[o][c];
                        acc[3 + c] += reference.rgb[o][c];
                    }
                }
                row += &format!(" {:.3}/{:.3}", acc[1] / 7.0, acc[4] / 7.0);
            }
            eprintln!("DIAG r{j}:{row}");
        }
    }
    (m.mean_de2000, m.p95_de2000)
}

/// Under a uniform environment the split sum is exact but for the BRDF table: the
/// renderer must match the integrating reference.
#[test]
fn sphere_grid_matches_the_reference_under_a_uniform_environment() {
    let uniform = EnvImage::uniform(Vec3::new(0.8, 0.9, 1.0));
    let (mean, p95) = grid_under(EnvView::new(Arc::new(Prefiltered::build(uniform))));
    eprintln!("uniform environment: mean ΔE00 {mean:.3} (p95 {p95:.3}) against the reference");
    assert!(mean < GRID_MEAN_DE, "mean ΔE00 {mean}");
}

/// Under an HDR environment the renderer's split sum (prefiltered chain, BRDF table, SH9
/// irradiance) against the reference's direct integral.
#[test]
fn sphere_grid_matches_the_reference_under_an_hdr_environment() {
    let (mean, p95) = grid_under(hdr_environment());
    eprintln!("HDR environment: mean ΔE00 {mean:.3} (p95 {p95:.3}) against the reference");
    assert!(mean < GRID_MEAN_DE, "mean ΔE00 {mean}");
}

/// Under the default rig and ambient light no sphere of the metal column is black: its
/// reflection of the ambient environment shows its colour.
#[test]
fn the_metal_column_is_not_black() {
    let scene = model("sphere-grid.glb");
    let n = 100;
    let opts = Shot {
        settings: Settings {
            lights: Lights::Auto,
            environment: Environment::Auto,
            ..options(n, n, grid_camera(), vec![]).settings
        },
        ..options(n, n, grid_camera(), vec![])
    };
    let frame = render(&PreparedScene::new(scene), &opts).image();
    for j in 0..5 {
        let (x, y) = centre(n, 2.0, 2.0 - j as f32);
        let c = frame.pixel(x, y).truncate();
        eprintln!("metal, roughness {}: {c}", j as f32 / 4.0);
        assert!(c.max_element() > 0.02, "metal sphere {j} is black: {c}");
        assert!(c.x > c.z, "metal reflects in its gold colour: {c}");
    }
}

/// `KHR_materials_emissive_strength`: with no light at all the right quad (strength 4)
/// glows four times as bright as the left one (the same emissiveFactor without it).
#[test]
fn emissive_strength_brightens_by_its_factor() {
    let scene = model("emissive-strength.glb");
    let cam = Camera {
        eye: Vec3::new(0.0, 0.0, 3.0),
        ..Camera::default()
    };
    let opts = options(64, 32, cam, vec![]);
    let frame = render(&PreparedScene::new(scene), &opts).image();
    let left = frame.pixel(19, 16).truncate();
    let right = frame.pixel(44, 16).truncate();
    eprintln!("emission: {left} and {right}");
    assert!(
        (left - Vec3::new(0.2, 0.1, 0.05)).abs().max_element() < 1e-6,
        "{left}"
    );
    assert!((right - left * 4.0).abs().max_element() < 1e-6, "{right}");
}

/// `KHR_materials_unlit`: the pixel is the base colour exactly (factor, factor times the
/// texel decoded from sRGB, factor times the vertex colour), whatever the lights.
#[test]
fn unlit_pixels_equal_the_base_colour_exactly() {
    let scene = model("unlit.glb");
    let cam = Camera {
        eye: Vec3::new(0.6, 0.0, 3.0),
        target: Vec3::new(0.6, 0.0, 0.0),
        ..Camera::default()
    };
    let factor = Vec3::new(0.25, 0.5, 0.75);
    let (w, h) = (96, 32);
    // World x at z = 0 to the pixel column: the view is 2 · 3 tan 22.5° high, 3x as wide.
    let column = |x: f32| {
        let half_width = 3.0 * libm::tanf(22.5f32.to_radians()) * 3.0;
        (((x - 0.6) / half_width * 0.5 + 0.5) * w as f32) as u32
    };
    for lights in [vec![], grid_lights()] {
        let opts = options(w, h, cam.clone(), lights);
        let frame = render(&PreparedScene::new(scene.clone()), &opts).image();
        // The factor-only quad.
        let c = frame.pixel(column(-0.6), h / 2).truncate();
        assert_eq!(c, factor, "unlit factor");
        // The textured quad: NEAREST, so one texel exactly, decoded from sRGB.
        let t = frame.pixel(column(0.6), h / 2).truncate();
        let ratio = t / factor;
        let decoded = [0u8, 85, 170, 255].map(|b| srgb_decode(f64::from(b) / 255.0));
        for r in ratio.to_array() {
            assert!(
                decoded.iter().any(|d| (f64::from(r) - d).abs() < 1e-6),
                "unlit texel {t}: {r} is not a decoded texel value"
            );
        }
        // The vertex-coloured quad: COLOR_0's green is 0.5 everywhere.
        let v = frame.pixel(column(1.8), h / 2).truncate();
        assert!((v.y - 0.25).abs() < 1e-6, "unlit vertex colour {v}");
        assert!(v.x > 0.0 && v.z > 0.0, "{v}");
    }
}

/// `KHR_materials_ior` and `KHR_materials_specular` change the dielectric's Fresnel: with
/// the light and the eye on the axis through each sphere's front point (an orthographic
/// view whose pixel centres fall exactly there: n = l = v, so N·H = V·H = 1 and F = F0),
/// the pixel is `E ((1 - max F0) c / π + F0 Vis D)` with `D = 1 / (π α²)` and `Vis = 1/4`,
/// written out here from the specification, not taken from the renderer.
#[test]
fn ior_and_specular_change_fresnel_as_the_formulas_say() {
    let scene = model("ior-specular.glb");
    let (w, h) = (260, 65);
    let cam = Camera {
        eye: Vec3::new(0.0, 0.0, 5.0),
        ortho: Some(0.5),
        near: 1.0,
        far: 10.0,
        ..Camera::default()
    };
    let opts = options(w, h, cam, vec![Light::directional(-Vec3::Z, Vec3::ONE)]);
    let frame = render(&PreparedScene::new(scene), &opts).image();
    let c = 0.5;
    let alpha = 0.3f64 * 0.3;
    let d = 1.0 / (PI * alpha * alpha);
    let vis = 0.25;
    let f0_ior = |ior: f64| ((ior - 1.0) / (ior + 1.0)).powi(2);
    let cases = [
        ("no extension", DVec3::splat(0.04)),
        ("ior 1.0", DVec3::splat(f0_ior(1.0))),
        ("ior 2.5", DVec3::splat(f0_ior(2.5))),
        (
            "specular 0.5, colour (1, 0.2, 0.2)",
            (DVec3::new(1.0, 0.2, 0.2) * 0.04).min(DVec3::ONE) * 0.5,
        ),
    ];
    for (k, (what, f0)) in cases.into_iter().enumerate() {
        let x = [32, 97, 162, 227][k];
        let got = frame.pixel(x, 32).truncate().as_dvec3();
        let want = DVec3::splat((1.0 - f0.max_element()) * c / PI) + f0 * vis * d;
        eprintln!("{what}: F0 {f0:.4}, pixel {got:.4}, formula {want:.4}");
        assert!(
            ((got - want) / want).abs().max_element() < 2e-3,
            "{what}: {got} against {want}"
        );
    }
}

/// The directional albedo of the single-scattering BRDF (`brdf::pbr` in f64, integrated
/// over the hemisphere by quadrature) of a white material with `metallic` at view angle
/// N·V = `nv`.
fn albedo(metallic: f32, roughness: f64, nv: f64) -> f64 {
    let surface = Surface {
        diffuse: Vec3::ONE,
        specular: Vec3::ZERO,
        ambient: Vec3::ONE,
        shininess: 1.0,
        pbr: Some(PbrParams {
            metallic,
            roughness: roughness as f32,
            ..PbrParams::default()
        }),
    };
    let s = surface.at::<f64>(DVec3::ONE);
    let p = s.pbr.expect("pbr");
    let a = brdf::alpha(p.roughness);
    let n = DVec3::Z;
    let v = DVec3::new((1.0 - nv * nv).sqrt(), 0.0, nv);
    // Midpoint rule in (cos θ, φ): dω = d(cos θ) dφ.
    let (nt, np) = (4000, 720);
    let mut sum = 0.0;
    for i in 0..nt {
        let ct = (i as f64 + 0.5) / nt as f64;
        let st = (1.0 - ct * ct).sqrt();
        for j in 0..np {
            let phi = (j as f64 + 0.5) / np as f64 * 2.0 * PI;
            let l = DVec3::new(st * libm::cos(phi), st * libm::sin(phi), ct);
            let t = brdf::pbr(&s, &p, a, n, l, v, ct);
            sum += (t.diffuse + t.specular).x;
        }
    }
    sum * 2.0 * PI / f64::from(nt * np)
}

/// The white furnace: the single-scattering BRDF loses energy at high roughness (white
/// metal reflects `Ess`: 1 - ln 2 = 0.307 head-on at roughness 1, 0.451 at N·V = 0.5,
/// about 0.92 at roughness 0.5), and the renderer's image-based term compensates it
/// (Fdez-Agüera's multiple scattering): in a uniform white environment (ambient light 1,
/// no other light) white metal and white dielectric spheres at every roughness reflect 1.
/// Measured (the README's table): single scattering head-on, metal 0.996, 0.916, 0.627,
/// 0.307 and dielectric 1.000, 0.997, 0.985, 0.972 at roughness 0.25, 0.5, 0.75, 1
/// (below 0.25 the quadrature cannot resolve the lobe); rendered, 1.0000 everywhere (the
/// compensated split sum gives white exactly 1 by construction; the test holds the
/// renderer to it).
#[test]
fn white_furnace() {
    let ess = |mu: f64| 1.0 - mu * libm::log(1.0 + 1.0 / mu);
    for (r, nv, want, tol) in [
        (1.0, 1.0, ess(1.0), 0.003),
        (1.0, 0.5, ess(0.5), 0.003),
        (0.5, 1.0, 0.92, 0.01),
    ] {
        let got = albedo(1.0, r, nv);
        eprintln!("single scattering, white metal, roughness {r}, N·V {nv}: albedo {got:.4}");
        assert!((got - want).abs() < tol, "{got} against {want}");
    }
    eprintln!("| roughness | metal, single scattering | dielectric, single scattering |");
    let mut previous = (2.0, 2.0);
    for r in [0.25, 0.5, 0.75, 1.0] {
        let (metal, dielectric) = (albedo(1.0, r, 1.0), albedo(0.0, r, 1.0));
        eprintln!("| {r} | {metal:.3} | {dielectric:.3} |");
        // The loss grows with roughness, and no single-scattering albedo exceeds 1.
        assert!(
            metal < previous.0 && dielectric < previous.1 + 1e-3,
            "roughness {r}"
        );
        assert!(
            metal <= 1.0 + 1e-3 && dielectric <= 1.0 + 1e-3,
            "roughness {r}"
        );
        previous = (metal, dielectric);
    }
    let scene = model("sphere-grid-white.glb");
    let n = 100;
    // One stop down, so a sphere reflecting more than it receives is not hidden by the
    // clamp at 1 of the default tone map: every sphere must read 0.5.
    let opts = Shot {
        settings: Settings {
            exposure: -1.0,
            ..options(n, n, grid_camera(), vec![Light::ambient(Vec3::ONE)]).settings
        },
        ..options(n, n, grid_camera(), vec![Light::ambient(Vec3::ONE)])
    };
    let frame = render(&PreparedScene::new(scene), &opts).image();
    let mut worst = 0.0f32;
    for j in 0..5 {
        let mut row = String::new();
        for i in [0, 4] {
            let (x, y) = centre(n, i as f32 - 2.0, 2.0 - j as f32);
            let c = frame.pixel(x, y).truncate();
            row += &format!(" {:.4}", 2.0 * c.x);
            worst = worst.max((2.0 * c - Vec3::ONE).abs().max_element());
        }
        eprintln!(
            "rendered, roughness {}: dielectric and metal{row}",
            j as f32 / 4.0
        );
    }
    eprintln!("furnace: white metal and dielectric, worst |albedo - 1| = {worst:.4}");
    assert!(worst < 0.02, "{worst}");
}

/// `KHR_materials_variants` (`variants.glb`: spheres "left" and "right", green by default;
/// "red" maps both to red, "blue" only the left one to blue, "none" maps nothing): each
/// variant draws the materials the file maps for it, the others keep their defaults, and
/// the command line's `--variant` draws the same image (and refuses a name the file lacks).
#[test]
fn material_variants_draw_the_materials_the_file_maps() {
    let scene = model("variants.glb");
    assert_eq!(scene.variants, ["red", "blue", "none"]);
    assert!(
        !scene
            .report
            .skipped
            .iter()
            .any(|s| s.contains("KHR_materials_variants")),
        "{:?}",
        scene.report.skipped
    );
    let prepared = PreparedScene::new(scene);
    let camera = Camera {
        eye: Vec3::new(0.0, 0.0, 4.0),
        target: Vec3::ZERO,
        near: 1.0,
        far: 10.0,
        ..Camera::default()
    };
    let n = 96;
    // The spheres' centres at x = -0.5 and 0.5 on the image's middle row.
    let half = 4.0 * libm::tanf(22.5f32.to_radians());
    let column = |x: f32| ((0.5 + x / (2.0 * half)) * n as f32) as u32;
    let lights = vec![
        Light::directional(Vec3::NEG_Z, Vec3::ONE),
        Light::ambient(Vec3::splat(0.2)),
    ];
    // The dominant channel (0 red, 1 green, 2 blue) at each sphere's centre.
    let hues = |variant: Option<&str>| {
        let mut opts = options(n, n, camera.clone(), lights.clone());
        opts.settings.variant = variant.map(str::to_owned);
        let img = render(&prepared, &opts).image();
        [-0.5f32, 0.5].map(|x| {
            let c = img.color[(n / 2 * n + column(x)) as usize];
            let c = [c.x, c.y, c.z];
            (0..3).max_by(|&a, &b| c[a].total_cmp(&c[b])).unwrap()
        })
    };
    assert_eq!(hues(None), [1, 1], "green by default");
    assert_eq!(hues(Some("red")), [0, 0], "red maps both");
    assert_eq!(hues(Some("blue")), [2, 1], "blue maps only the left one");
    assert_eq!(hues(Some("none")), [1, 1], "none maps nothing");
    assert_eq!(
        hues(Some("not a variant")),
        [1, 1],
        "an unknown name draws the defaults"
    );

    // The command line: --variant blue against the default, and a name the file lacks.
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/pbr/variants.glb");
    let dir = std::env::temp_dir().join(format!("realist-variants-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = |extra: &[&str], out: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_realist"))
            .arg("render")
            .arg(&file)
            .args(["--size", "64x64", "-o"])
            .arg(dir.join(out))
            .args(extra)
            .output()
            .expect("realist runs")
    };
    let plain = run(&[], "plain.png");
    let blue = run(&["--variant", "blue"], "blue.png");
    assert!(plain.status.success() && blue.status.success(), "{blue:?}");
    let read = |name: &str| image::open(dir.join(name)).expect("png").into_rgb8();
    let (p, b) = (read("plain.png"), read("blue.png"));
    let left = |img: &image::RgbImage| img.get_pixel(64 * 3 / 8, 32).0;
    assert!(
        left(&b)[2] > left(&b)[1],
        "left sphere blue: {:?}",
        left(&b)
    );
    assert!(
        left(&p)[1] > left(&p)[2],
        "left sphere green: {:?}",
        left(&p)
    );
    let bad = run(&["--variant", "purple"], "bad.png");
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(!bad.status.success());
    assert!(
        err.contains("--variant purple")
            && err.contains("variants.glb")
            && err.contains("it has: red, blue, none"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `KHR_animation_pointer` (`pointer.glb`, see `models/README.md`): the material's base
/// colour (LINEAR red, blue, red at t = 0, 1, 2), emissive (STEP black, then (0.2, 0.2, 0)
/// from t = 1), roughness (LINEAR 0.2 to 0.8 over 2 s) and emissive strength (1 to 3), the
/// node's translation through a pointer (LINEAR x 0 to 0.5), the spot light's intensity (10
/// to 30), colour (STEP) and outer cone (0.5 to 0.7), and the camera's yfov (0.6 to 0.9),
/// each at the times the file gives, evaluated here from the keys; `realist render --time`
/// draws the posed colour.
#[test]
fn animation_pointers_set_material_factors_at_the_files_times() {
    use realist::scene::anim::Property;
    let scene = model("pointer.glb");
    assert!(
        scene.report.warnings.is_empty(),
        "{:?}",
        scene.report.warnings
    );
    assert!(
        !scene
            .report
            .skipped
            .iter()
            .any(|s| s.contains("KHR_animation_pointer")),
        "{:?}",
        scene.report.skipped
    );
    let a = &scene.animations[0];
    let props: Vec<Property> = a.channels.iter().map(|c| c.property).collect();
    assert_eq!(
        props,
        [
            Property::BaseColor,
            Property::Emissive,
            Property::Roughness,
            Property::Translation,
            Property::EmissiveStrength,
            Property::LightIntensity,
            Property::LightColor,
            Property::SpotOuter,
            Property::CameraYfov,
        ]
    );
    let mut prepared = PreparedScene::new(scene);
    let (red, blue) = (
        glam::Vec4::new(0.8, 0.1, 0.1, 1.0),
        glam::Vec4::new(0.1, 0.1, 0.8, 1.0),
    );
    for t in [0.0f32, 0.25, 0.5, 1.0, 1.5, 2.0, 3.0] {
        prepared.pose_at(realist::scene::Play::All, t, false);
        let m = prepared.material(0).expect("the material");
        let u = t.clamp(0.0, 2.0);
        let want = if u <= 1.0 {
            red.lerp(blue, u)
        } else {
            blue.lerp(red, u - 1.0)
        };
        assert!(
            (m.base_color - want).abs().max_element() < 1e-6,
            "t {t}: {} vs {want}",
            m.base_color
        );
        let emissive = if t < 1.0 {
            Vec3::ZERO
        } else {
            Vec3::new(0.2, 0.2, 0.0)
        };
        assert!(
            (m.emissive - emissive).abs().max_element() < 1e-6,
            "t {t}: {}",
            m.emissive
        );
        assert!(
            (m.roughness - (0.2 + 0.3 * u)).abs() < 1e-6,
            "t {t}: {}",
            m.roughness
        );
        let (lo, hi) = prepared.bounds().expect("bounds");
        assert!(
            ((lo.x + hi.x) * 0.5 - 0.25 * u).abs() < 1e-3,
            "t {t}: {lo} {hi}"
        );
        let strength = m.pbr.as_ref().expect("pbr").emissive_strength;
        assert!((strength - (1.0 + u)).abs() < 1e-6, "t {t}: {strength}");
        // The spot light "lamp" and the camera "view".
        let lamp = &prepared.lights()[0];
        assert!(
            (lamp.intensity - (10.0 + 10.0 * u)).abs() < 1e-5,
            "t {t}: {}",
            lamp.intensity
        );
        let colour = if t < 1.0 {
            Vec3::ONE
        } else {
            Vec3::new(1.0, 0.5, 0.25)
        };
        assert_eq!(lamp.color, colour, "t {t}");
        assert!(
            (lamp.outer - (0.5 + 0.1 * u)).abs() < 1e-6,
            "t {t}: {}",
            lamp.outer
        );
        assert!(
            (lamp.inner - 0.2).abs() < 1e-6,
            "the inner cone is not animated"
        );
        let yfov = prepared.cameras()[0].yfov;
        assert!((yfov - (0.6 + 0.15 * u)).abs() < 1e-6, "t {t}: {yfov}");
    }
    // Back at rest, the file's own factors.
    prepared.pose_at(realist::scene::Play::Rest, 0.0, false);
    assert_eq!(prepared.material(0).unwrap().base_color, red);
    assert_eq!(prepared.lights()[0].intensity, 10.0);
    assert_eq!(prepared.cameras()[0].yfov, 0.6);
    // The command line at t = 1: the ball is blue (t = 0: red), over the whole image
    // (the lamp's highlight and the emission whiten the middle).
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/pbr/pointer.glb");
    let dir = std::env::temp_dir().join(format!("realist-pointer-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let blue_minus_red = |t: &str| {
        let out = dir.join(format!("t{t}.png"));
        let r = std::process::Command::new(env!("CARGO_BIN_EXE_realist"))
            .arg("render")
            .arg(&file)
            .args(["--size", "64x64", "--time", t, "-o"])
            .arg(&out)
            .output()
            .expect("realist runs");
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let img = image::open(&out).expect("png").into_rgb8();
        img.pixels()
            .map(|p| i64::from(p[2]) - i64::from(p[0]))
            .sum::<i64>()
    };
    let (d0, d1) = (blue_minus_red("0"), blue_minus_red("1"));
    assert!(d1 > d0 + 20_000, "t = 0: {d0}, t = 1: {d1}");
    // Through the file's camera, whose yfov widens from 0.6 to 0.9: the ball's area shrinks
    // by (tan 0.3 / tan 0.45)² = 0.41.
    let covered = |t: &str| {
        let out = dir.join(format!("cam{t}.png"));
        let r = std::process::Command::new(env!("CARGO_BIN_EXE_realist"))
            .arg("render")
            .arg(&file)
            .args(["--size", "64x64", "--camera", "gltf:0", "--time", t, "-o"])
            .arg(&out)
            .output()
            .expect("realist runs");
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let img = image::open(&out).expect("png").into_rgb8();
        let bg = *img.get_pixel(0, 0);
        img.pixels().filter(|p| **p != bg).count() as f64
    };
    let (a0, a2) = (covered("0"), covered("2"));
    let ratio = a2 / a0;
    let want = (libm::tan(0.3f64) / libm::tan(0.45f64)).powi(2);
    assert!(
        (ratio - want).abs() < 0.1,
        "area {a0} -> {a2}: {ratio}, want {want}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
