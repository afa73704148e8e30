//! The references and the sweep, checked against closed forms and each other.

use glam::Vec3;

use super::sphere::SphereSetup;
use super::{compare, metrics, sweep};
use crate::scene::{Camera, Light};
use crate::shade::Shading;

#[test]
fn sphere_reference_coverage_is_the_projected_disc() {
    // Head-on, ambient light only, white: every pixel's value is its coverage.
    let (w, h, d) = (200u32, 160u32, 4.0f32);
    let mut setup = SphereSetup::standard(w, h);
    setup.camera = Camera {
        eye: Vec3::new(0.0, 0.0, d),
        ..Camera::orbit(Vec3::ZERO, 0.0, 0.0, d, 0.8)
    };
    setup.lights = vec![Light::Ambient { color: Vec3::ONE }];
    setup.material.base_color = glam::Vec4::ONE;
    setup.material.ambient = Vec3::ONE;
    let img = setup.reference(false);
    let covered: f64 = img.rgb.iter().map(|c| c[0]).sum();
    // Silhouette radius in pixels: tan(asin(1/d)) / tan(fov/2) * h/2.
    let d = f64::from(d);
    let r = (1.0 / (d * d - 1.0).sqrt()) / (0.4f64).tan() * f64::from(h) / 2.0;
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
        let s = sweep::Setting {
            slices,
            stacks,
            shading: Shading::Phong,
            ss,
        };
        let (_, img) = sweep::run_setting(&setup, s, 1).unwrap();
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
    let s = sweep::Setting {
        slices: 256,
        stacks: 128,
        shading: Shading::Blinn,
        ss: 4,
    };
    let (_, img) = sweep::run_setting(&setup, s, 1).unwrap();
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
    let s = sweep::Setting {
        slices: 8,
        stacks: 4,
        shading: Shading::Phong,
        ss: 1,
    };
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
        let s = sweep::Setting {
            slices,
            stacks: 1,
            shading: Shading::Phong,
            ss,
        };
        let (_, img) = sweep::run_setting(&setup, s, 1).unwrap();
        compare(&img, &reference, metrics::DEFAULT_DE_THRESHOLD).mean_de2000
    };
    let (coarse, fine, fine_ss) = (error(6, 1), error(256, 1), error(256, 4));
    assert!(
        coarse > 2.0 * fine && fine > 2.0 * fine_ss,
        "{coarse} {fine} {fine_ss}"
    );
    assert!(fine_ss < 0.05, "{fine_ss}");
}
