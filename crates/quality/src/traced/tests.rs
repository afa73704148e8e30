//! The path tracer in `f32` against its `f64` copy on the same random numbers.

use super::{Light, Precision, TracedSetup};
use crate::metrics::{compare, DEFAULT_DE_THRESHOLD};

/// The `f32` path tracer and the `f64` one draw the same random numbers, so they trace the
/// same paths but where rounding sends one another way (a ray grazing an edge, a choice
/// made on a rounded weight): on both traced scenes, with every bounce, their difference is
/// a small part of the noise between two `f64` runs from different streams, and most
/// pixels agree to 1e-4.
#[test]
fn f32_paths_match_the_f64_reference_on_the_same_stream() {
    for light in [Light::Shadows, Light::Environment] {
        let t = TracedSetup::standard(light, 96, 54, 4);
        let f64_image = t.path_in(Precision::F64, true, 4, 11, true);
        let f32_image = t.path_in(Precision::F32, true, 4, 11, true);
        let other = t.path_in(Precision::F64, true, 4, 12, true);
        let rounding = compare(&f32_image, &f64_image, DEFAULT_DE_THRESHOLD);
        let noise = compare(&other, &f64_image, DEFAULT_DE_THRESHOLD);
        let close = f32_image
            .rgb
            .iter()
            .zip(&f64_image.rgb)
            .filter(|(a, b)| (0..3).all(|k| (a[k] - b[k]).abs() <= 1e-4 * (1.0 + b[k].abs())))
            .count();
        let share = close as f64 / f64_image.rgb.len() as f64;
        println!(
            "{}: f32 vs f64 mean dE00 {:.5} (max abs {:.2e}), {:.1}% of pixels within 1e-4; \
             noise between streams {:.4}",
            light.name(),
            rounding.mean_de2000,
            rounding.max_abs,
            share * 100.0,
            noise.mean_de2000
        );
        assert!(
            noise.mean_de2000 > 0.05,
            "{light:?}: no noise to compare with"
        );
        assert!(
            rounding.mean_de2000 < 0.1 * noise.mean_de2000,
            "{light:?}: f32 vs f64 {} against noise {}",
            rounding.mean_de2000,
            noise.mean_de2000
        );
        assert!(share > 0.99, "{light:?}: only {share} of pixels agree");
    }
}
