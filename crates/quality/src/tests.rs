//! The references and the sweep, checked against closed forms and each other.

use glam::Vec3;

use super::plane::{self, PlaneSetup};
use super::sphere::SphereSetup;
use super::{compare, metrics, sweep};
use crate::scene::{Camera, Light};
use crate::shade::Shading;
use crate::texture::Filter;

/// An analytic-shape setting at full sub-pixel precision, textures untouched.
fn shape_setting(slices: u32, stacks: u32, shading: Shading, ss: u32) -> sweep::Setting {
    sweep::Setting {
        slices,
        stacks,
        shading,
        ss,
        msaa: 1,
        filter: None,
        bits: 8,
        shadow_size: 0,
        pcf: 0,
        global: false,
    }
}

#[test]
fn sphere_reference_coverage_is_the_projected_disc() {
    // Head-on, ambient light only, white: every pixel's value is its coverage.
    let (w, h, d) = (200u32, 160u32, 4.0f32);
    let mut setup = SphereSetup::standard(w, h);
    setup.camera = Camera {
        eye: Vec3::new(0.0, 0.0, d),
        ..Camera::orbit(Vec3::ZERO, 0.0, 0.0, d, 0.8)
    };
    setup.lights = vec![Light::ambient(Vec3::ONE)];
    setup.material.base_color = glam::Vec4::ONE;
    setup.material.ambient = Vec3::ONE;
    let img = setup.reference(false);
    let covered: f64 = img.rgb.iter().map(|c| c[0]).sum();
    // Silhouette radius in pixels: tan(asin(1/d)) / tan(fov/2) * h/2.
    let d = f64::from(d);
    let r = (1.0 / (d * d - 1.0).sqrt()) / libm::tan(0.4f64) * f64::from(h) / 2.0;
    let disc = std::f64::consts::PI * r * r;
    assert!(
        (covered / disc - 1.0).abs() < 2e-4,
        "covered {covered}, disc {disc}"
    );
    assert!(img.rgb.iter().all(|c| (0.0..=1.0 + 1e-12).contains(&c[0])));
}

#[test]
fn rasterized_sphere_converges_to_the_reference() {
    let setup = SphereSetup::standard(160, 90);
    let reference = setup.reference(false);
    let error = |slices, stacks, ss| {
        let s = shape_setting(slices, stacks, Shading::Phong, ss);
        let (_, img) = sweep::run_setting(&sweep::Subject::Shape(setup.clone()), s, 1).unwrap();
        compare(&img, &reference, metrics::DEFAULT_DE_THRESHOLD).mean_de2000
    };
    let (coarse, mid, fine, fine_ss) = (
        error(8, 4, 1),
        error(32, 16, 1),
        error(256, 128, 1),
        error(256, 128, 4),
    );
    assert!(
        coarse > 2.0 * mid && mid > fine && fine > 2.0 * fine_ss,
        "{coarse} {mid} {fine} {fine_ss}"
    );
    assert!(fine_ss < 0.05, "{fine_ss}");
    // Blinn against the Blinn reference is as close as Phong against Phong.
    let blinn = setup.reference(true);
    let s = shape_setting(256, 128, Shading::Blinn, 4);
    let (_, img) = sweep::run_setting(&sweep::Subject::Shape(setup.clone()), s, 1).unwrap();
    assert!(compare(&img, &blinn, 1.0).mean_de2000 < 0.05);
    assert!(compare(&img, &reference, 1.0).mean_de2000 > compare(&img, &blinn, 1.0).mean_de2000);
}

#[test]
fn pareto_front_keeps_only_undominated_rows() {
    let m = |de: f64| metrics::Metrics {
        rmse: 0.0,
        psnr: 0.0,
        max_abs: 0.0,
        mean_de2000: de,
        p95_de2000: 0.0,
        over_threshold: 0,
    };
    let s = shape_setting(8, 4, Shading::Phong, 1);
    let rows: Vec<sweep::Row> = [(1.0, 3.0), (2.0, 4.0), (3.0, 1.0), (4.0, 1.5), (5.0, 0.5)]
        .iter()
        .map(|&(ms, de)| sweep::Row {
            knob: "tessellation",
            setting: s,
            ms,
            metrics: m(de),
        })
        .collect();
    assert_eq!(sweep::pareto(&rows), vec![0, 2, 4]);
    let csv = sweep::csv(&rows, &[0, 2, 4]);
    assert_eq!(csv.lines().count(), 6);
    assert!(
        csv.lines().nth(1).unwrap().ends_with(",true")
            && csv.lines().nth(2).unwrap().ends_with(",false")
    );
}

#[test]
fn rasterized_cylinder_converges_to_the_reference() {
    let setup = SphereSetup::standard_shape(super::sphere::Shape::Cylinder, 160, 90);
    let reference = setup.reference(false);
    // The cylinder fills a fair part of the frame, caps included.
    let covered = reference
        .rgb
        .iter()
        .filter(|c| c.iter().any(|&v| v > 0.0))
        .count();
    assert!(covered > 160 * 90 / 8, "{covered}");
    let error = |slices, ss| {
        let s = shape_setting(slices, 1, Shading::Phong, ss);
        let (_, img) = sweep::run_setting(&sweep::Subject::Shape(setup.clone()), s, 1).unwrap();
        compare(&img, &reference, metrics::DEFAULT_DE_THRESHOLD).mean_de2000
    };
    let (coarse, fine, fine_ss) = (error(6, 1), error(256, 1), error(256, 4));
    assert!(
        coarse > 2.0 * fine && fine > 2.0 * fine_ss,
        "{coarse} {fine} {fine_ss}"
    );
    assert!(fine_ss < 0.05, "{fine_ss}");
}

/// The plane with a uniform texture under ambient light 1: the reference is the coverage.
fn uniform_plane(w: u32, h: u32, texel: [u8; 4]) -> PlaneSetup {
    let mut setup = PlaneSetup::standard(w, h);
    setup.lights = vec![Light::ambient(Vec3::ONE)];
    setup.texture = std::sync::Arc::new(
        crate::texture::Texture::new("uniform", 4, 4, vec![texel; 16], true).unwrap(),
    );
    setup
}

#[test]
fn plane_reference_coverage_is_the_projected_quad() {
    let setup = uniform_plane(320, 180, [255; 4]);
    let img = setup.reference();
    let covered: f64 = img.rgb.iter().map(|c| c[0]).sum();
    let area = plane::visible_area(&setup);
    assert!(area > 320.0 * 180.0 * 0.4, "{area}");
    assert!(
        (covered / area - 1.0).abs() < 1e-9,
        "covered {covered}, area {area}"
    );
    assert!(img
        .rgb
        .iter()
        .all(|c| (0.0..=1.0 + 1e-9).contains(&c[0]) && c[0] == c[1] && c[1] == c[2]));
    // Below the far edge's silhouette every pixel is wholly covered.
    let bottom = &img.rgb[(170 * 320) as usize..];
    assert!(bottom.iter().all(|c| (c[0] - 1.0).abs() < 1e-9));
}

#[test]
fn plane_interior_of_a_uniform_texture_is_exact_in_the_rasterizer_too() {
    // Grey 128: the rasterizer's texel decode and lighting agree with the f64 reference to
    // f32 rounding wherever a pixel is wholly covered.
    let setup = uniform_plane(160, 90, [128, 128, 128, 255]);
    let reference = setup.reference();
    let subject = sweep::Subject::Plane(setup);
    for filter in [Filter::Nearest, Filter::Bilinear] {
        let s = sweep::Setting {
            slices: 0,
            stacks: 0,
            shading: Shading::Textured,
            ss: 1,
            msaa: 1,
            filter: Some(filter),
            bits: 8,
            shadow_size: 0,
            pcf: 0,
            global: false,
        };
        let (_, img) = sweep::run_setting(&subject, s, 1).unwrap();
        let expect = crate::color::srgb_decode(128.0 / 255.0);
        let mut interior = 0;
        for (a, r) in img.rgb.iter().zip(&reference.rgb) {
            if (r[0] - expect).abs() < 1e-12 {
                assert!((a[0] - expect).abs() < 1e-6, "{a:?} vs {expect}");
                interior += 1;
            }
        }
        assert!(interior > 160 * 90 / 3, "{interior}");
    }
}

#[test]
fn plane_supersampling_converges_to_the_exact_filter() {
    let setup = PlaneSetup::standard(320, 180);
    let reference = setup.reference();
    let subject = sweep::Subject::Plane(setup);
    let error = |filter, ss| {
        let s = sweep::Setting {
            slices: 0,
            stacks: 0,
            shading: Shading::Textured,
            ss,
            msaa: 1,
            filter: Some(filter),
            bits: 8,
            shadow_size: 0,
            pcf: 0,
            global: false,
        };
        let (_, img) = sweep::run_setting(&subject, s, 1).unwrap();
        compare(&img, &reference, metrics::DEFAULT_DE_THRESHOLD)
    };
    let (n1, n2, n4) = (
        error(Filter::Nearest, 1),
        error(Filter::Nearest, 2),
        error(Filter::Nearest, 4),
    );
    // Point sampling of a picture: the error halves with each doubling of the samples.
    assert!(
        n1.mean_de2000 > 1.6 * n2.mean_de2000 && n2.mean_de2000 > 1.6 * n4.mean_de2000,
        "{n1:?} {n2:?} {n4:?}"
    );
    assert!(n1.rmse > n2.rmse && n2.rmse > n4.rmse);
    // Mipmaps remove most of the minification aliasing that a single bilinear tap keeps.
    let (b1, t1) = (error(Filter::Bilinear, 1), error(Filter::Trilinear, 1));
    assert!(t1.rmse < 0.85 * b1.rmse, "{t1:?} {b1:?}");
}

#[test]
fn anisotropic_filtering_beats_trilinear_on_the_grazing_plane() {
    let setup = PlaneSetup::standard(320, 180);
    let reference = setup.reference();
    let subject = sweep::Subject::Plane(setup);
    // The sweep reports every filter on the plane.
    let filters: Vec<_> = subject
        .settings()
        .iter()
        .filter(|(_, s)| s.ss == 1)
        .filter_map(|(_, s)| s.filter)
        .collect();
    assert_eq!(filters, Filter::COMMON.to_vec());
    let error = |filter| {
        let s = sweep::Setting {
            slices: 0,
            stacks: 0,
            shading: Shading::Textured,
            ss: 1,
            msaa: 1,
            filter: Some(filter),
            bits: 8,
            shadow_size: 0,
            pcf: 0,
            global: false,
        };
        let (_, img) = sweep::run_setting(&subject, s, 1).unwrap();
        compare(&img, &reference, metrics::DEFAULT_DE_THRESHOLD)
    };
    let tri = error(Filter::Trilinear);
    let a2 = error(Filter::Anisotropic(2));
    let a16 = error(Filter::Anisotropic(16));
    eprintln!(
        "mean dE00 / rmse: trilinear {:.4} / {:.5}, aniso:2 {:.4} / {:.5}, aniso:16 {:.4} / {:.5}",
        tri.mean_de2000, tri.rmse, a2.mean_de2000, a2.rmse, a16.mean_de2000, a16.rmse
    );
    // Trilinear blurs the long, thin footprints of a grazing view along their short axis;
    // anisotropic taps keep that axis at its own scale.
    assert!(
        a16.mean_de2000 < 0.9 * tri.mean_de2000,
        "{a16:?} vs {tri:?}"
    );
    assert!(a16.rmse < tri.rmse, "{a16:?} vs {tri:?}");
    assert!(a2.mean_de2000 < tri.mean_de2000, "{a2:?} vs {tri:?}");
}

#[test]
fn coarser_subpixel_snap_costs_accuracy() {
    let setup = SphereSetup::standard(320, 180);
    let reference = setup.reference(false);
    let subject = sweep::Subject::Shape(setup);
    let rmse = |bits| {
        let s = sweep::Setting {
            slices: 256,
            stacks: 128,
            shading: Shading::Phong,
            ss: 1,
            msaa: 1,
            filter: None,
            bits,
            ..sweep::Setting::default()
        };
        let (_, img) = sweep::run_setting(&subject, s, 1).unwrap();
        compare(&img, &reference, metrics::DEFAULT_DE_THRESHOLD).rmse
    };
    let (b0, b4, b8) = (rmse(0), rmse(4), rmse(8));
    assert!(b0 > 1.1 * b8 && b4 < 1.02 * b8, "{b0} {b4} {b8}");
}

#[test]
fn model_sweep_measures_each_mode_against_its_own_ideal() {
    // An untextured scene: lit shading modes, Phong against the Phong ideal.
    // The reference draws no shadows: the demo's spotlight casts none here.
    let mut scene = crate::scene::demo();
    scene.lights.iter_mut().for_each(|l| l.shadow = false);
    let demo = sweep::ModelSetup::new(scene, 160, 90, 4);
    assert!(!demo.textured());
    let subject = sweep::Subject::Model(demo);
    let knobs: Vec<_> = subject.settings().iter().map(|(k, _)| *k).collect();
    assert!(knobs.contains(&"shading") && !knobs.contains(&"filter"));
    let phong = shape_setting(0, 0, Shading::Phong, 4);
    let (_, img) = sweep::run_setting(&subject, phong, 1).unwrap();
    let ideal = subject.reference(subject.reference_index(&phong)).unwrap();
    let blinn = subject.reference(1).unwrap();
    let good = compare(&img, &ideal, 1.0).mean_de2000;
    assert!(good < 0.1, "{good}");
    assert!(compare(&img, &blinn, 1.0).mean_de2000 > 2.0 * good);

    // A textured scene: the textured mode and the filter knob.
    let floor = PlaneSetup::standard(160, 90);
    let mut model = sweep::ModelSetup::new(floor.scene(Filter::Bilinear), 160, 90, 4);
    model.camera = floor.camera.clone();
    assert!(model.textured());
    let subject = sweep::Subject::Model(model);
    let settings = subject.settings();
    assert!(settings.iter().all(|(_, s)| s.shading == Shading::Textured));
    assert!(settings.iter().any(|(k, _)| *k == "filter"));
    let s = settings[0].1;
    assert_eq!(subject.reference_index(&s), 2);
}

#[test]
fn multisampling_halves_the_silhouette_error() {
    let setup = SphereSetup::standard(160, 90);
    let reference = setup.reference(false);
    let run = |ss, msaa| {
        let s = sweep::Setting {
            msaa,
            ..shape_setting(256, 128, Shading::Phong, ss)
        };
        let (_, img) = sweep::run_setting(&sweep::Subject::Shape(setup.clone()), s, 1).unwrap();
        compare(&img, &reference, metrics::DEFAULT_DE_THRESHOLD)
    };
    let (one, ms4, ss4) = (run(1, 1), run(1, 4), run(4, 1));
    eprintln!(
        "mean dE / px > 1 dE: 1 sample {:.4} / {}, msaa4 {:.4} / {}, ss 4x4 {:.4} / {}",
        one.mean_de2000,
        one.over_threshold,
        ms4.mean_de2000,
        ms4.over_threshold,
        ss4.mean_de2000,
        ss4.over_threshold
    );
    // The interior is shaded once per pixel as without multisampling; most of the
    // silhouette's aliasing goes (measured 0.196 -> 0.087). Four samples quantise an edge
    // pixel's coverage to quarters, so sixteen supersamples stay ahead (0.022), and edge
    // pixels over 1 ΔE00 fall little (233 -> 207; 120 with sixteen).
    assert!(ms4.mean_de2000 < 0.5 * one.mean_de2000, "{one:?} {ms4:?}");
    assert!(ms4.over_threshold < one.over_threshold, "{one:?} {ms4:?}");
    assert!(ss4.mean_de2000 < ms4.mean_de2000, "{ss4:?} {ms4:?}");
}

/// `whitted`'s traced shadows are exact where the rasterizer samples (pixel centres): on the
/// traced shadows stage they match the path tracer's direct light at pixel centres but for
/// a few pixels along silhouettes, including the ground far off at a grazing angle, where
/// a depth buffer's point lies furthest from its surface.
#[test]
fn traced_shadows_match_the_direct_light_at_pixel_centres() {
    use crate::traced::{Light, Reference, TracedSetup};
    let t = TracedSetup::standard(Light::Shadows, 320, 180, 1);
    let subject = sweep::Subject::Traced(t.clone());
    let reference = t.reference(Reference::Centres);
    let setting = |shading, shadow_size| sweep::Setting {
        shading,
        shadow_size,
        pcf: u32::from(shadow_size > 0),
        ..sweep::Setting::default()
    };
    let (_, traced) = sweep::run_setting(&subject, setting(Shading::Whitted, 0), 1).unwrap();
    let (_, mapped) = sweep::run_setting(&subject, setting(Shading::Pbr, 256), 1).unwrap();
    let (tm, mm) = (
        compare(&traced, &reference, metrics::DEFAULT_DE_THRESHOLD),
        compare(&mapped, &reference, metrics::DEFAULT_DE_THRESHOLD),
    );
    eprintln!(
        "traced: mean dE00 {:.4}, {} px > 1; 256-texel shadow map: {:.4}, {} px > 1",
        tm.mean_de2000, tm.over_threshold, mm.mean_de2000, mm.over_threshold
    );
    assert!(
        tm.over_threshold < 60 && tm.mean_de2000 < 0.02,
        "traced shadows: {} pixels over 1 dE00, mean {}",
        tm.over_threshold,
        tm.mean_de2000
    );
    assert!(
        mm.over_threshold > 4 * tm.over_threshold,
        "the shadow map is as exact"
    );
}

/// `pbr` lights every point by the whole environment: beside the objects and under them,
/// where the path tracer's direct light is blocked, its error stands well above the
/// reference's own noise.
#[test]
fn unoccluded_environment_light_errs_above_the_path_tracers_noise() {
    use crate::traced::{Light, Reference, TracedSetup};
    let t = TracedSetup::standard(Light::Environment, 128, 72, 8);
    let subject = sweep::Subject::Traced(t.clone());
    let reference = t.reference(Reference::Areas);
    let noise = t.noise(&reference);
    let setting = sweep::Setting {
        shading: Shading::Pbr,
        ss: 2,
        ..sweep::Setting::default()
    };
    let (_, img) = sweep::run_setting(&subject, setting, 1).unwrap();
    let m = compare(&img, &reference, metrics::DEFAULT_DE_THRESHOLD);
    eprintln!(
        "unoccluded environment: mean dE00 {:.4}; reference noise {:.4}",
        m.mean_de2000, noise.mean_de2000
    );
    assert!(
        m.mean_de2000 > 2.0 * noise.mean_de2000,
        "unoccluded {} against noise {}",
        m.mean_de2000,
        noise.mean_de2000
    );
}
