//! Error metrics between a test image and a reference, both linear light:
//!
//! - RMSE over all channels and PSNR = 20 log10(1 / RMSE) (peak 1.0, linear light);
//! - the largest absolute channel difference;
//! - CIEDE2000 of the colours as displayed (clamped to [0, 1], sRGB primaries, D65): mean,
//!   95th percentile, and the number of pixels above a threshold (default 1.0, about one
//!   just-noticeable difference);
//! - an error heat map (ΔE00 through a black-red-yellow-white ramp, saturating at 5).

use super::LinearImage;
use rayon::prelude::*;

use crate::color::{delta_e_2000, xyz_to_lab, Illuminant, Observer, RgbSpace};

/// ΔE00 above which a pixel counts as visibly different.
pub const DEFAULT_DE_THRESHOLD: f64 = 1.0;
/// ΔE00 at which the heat map saturates to white.
pub const HEAT_MAP_MAX_DE: f64 = 5.0;

/// Differences between two images.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metrics {
    pub rmse: f64,
    /// In dB; infinite for identical images.
    pub psnr: f64,
    pub max_abs: f64,
    pub mean_de2000: f64,
    pub p95_de2000: f64,
    /// Pixels whose ΔE00 exceeds the threshold given to [`compare`].
    pub over_threshold: usize,
}

/// Per-pixel ΔE00 of the displayed colours.
#[must_use]
pub fn delta_e_map(test: &LinearImage, reference: &LinearImage) -> Vec<f64> {
    let space = RgbSpace::srgb();
    let white = Illuminant::D65.xyz(Observer::Cie1931);
    let lab = |c: [f64; 3]| xyz_to_lab(space.linear_to_xyz(c.map(|v| v.clamp(0.0, 1.0))), white);
    test.rgb
        .par_iter()
        .zip(&reference.rgb)
        .map(|(&a, &b)| delta_e_2000(lab(a), lab(b)))
        .collect()
}

/// The heat-map colour of one ΔE00 value: black (0) through red and yellow to white
/// ([`HEAT_MAP_MAX_DE`] and above), 8-bit sRGB.
#[must_use]
pub fn heat_color(de: f64) -> [u8; 3] {
    let t = (de / HEAT_MAP_MAX_DE).clamp(0.0, 1.0) * 3.0;
    let q = |v: f64| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    [q(t), q(t - 1.0), q(t - 2.0)]
}

/// Mean and 95th percentile of a ΔE map (0 for an empty one).
#[must_use]
pub fn mean_p95(de: &[f64]) -> (f64, f64) {
    let mean = de.iter().sum::<f64>() / de.len().max(1) as f64;
    let mut sorted = de.to_vec();
    sorted.sort_unstable_by(f64::total_cmp);
    let p95 = sorted
        .get(((sorted.len() as f64 * 0.95).ceil() as usize).saturating_sub(1))
        .copied()
        .unwrap_or(0.0);
    (mean, p95)
}

/// Compares `test` with `reference` (same size).
///
/// # Panics
/// If the sizes differ.
#[must_use]
pub fn compare(test: &LinearImage, reference: &LinearImage, threshold: f64) -> Metrics {
    assert_eq!(
        (test.width, test.height),
        (reference.width, reference.height),
        "image sizes differ"
    );
    let mut sq = 0.0;
    let mut max_abs: f64 = 0.0;
    for (a, b) in test.rgb.iter().zip(&reference.rgb) {
        for k in 0..3 {
            let d = a[k] - b[k];
            sq += d * d;
            max_abs = max_abs.max(d.abs());
        }
    }
    let n = (test.rgb.len() * 3).max(1) as f64;
    let rmse = (sq / n).sqrt();
    let de = delta_e_map(test, reference);
    let over = de.iter().filter(|&&d| d > threshold).count();
    let (mean, p95) = mean_p95(&de);
    Metrics {
        rmse,
        psnr: if rmse > 0.0 {
            -20.0 * libm::log10(rmse)
        } else {
            f64::INFINITY
        },
        max_abs,
        mean_de2000: mean,
        p95_de2000: p95,
        over_threshold: over,
    }
}

/// The ΔE00 heat map as 8-bit RGB: black (0) through red and yellow to white
/// ([`HEAT_MAP_MAX_DE`] and above).
#[must_use]
pub fn heat_map(test: &LinearImage, reference: &LinearImage) -> Vec<u8> {
    delta_e_map(test, reference)
        .into_iter()
        .flat_map(heat_color)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_and_known_differences() {
        let a = LinearImage::filled(8, 4, [0.2, 0.4, 0.6]);
        let m = compare(&a, &a, DEFAULT_DE_THRESHOLD);
        assert_eq!(
            (m.rmse, m.max_abs, m.mean_de2000, m.over_threshold),
            (0.0, 0.0, 0.0, 0)
        );
        assert!(m.psnr.is_infinite());
        let mut b = a.clone();
        b.rgb[5] = [0.3, 0.4, 0.6];
        let m = compare(&b, &a, DEFAULT_DE_THRESHOLD);
        // One channel of 96 off by 0.1: RMSE = sqrt(0.01 / 96).
        assert!((m.rmse - (0.01f64 / 96.0).sqrt()).abs() < 1e-12, "{m:?}");
        assert!((m.max_abs - 0.1).abs() < 1e-12);
        assert_eq!(m.over_threshold, 1);
        assert!(
            m.mean_de2000 > 0.0 && m.p95_de2000 == 0.0,
            "one pixel of 32 is above the 95th percentile: {m:?}"
        );
        let heat = heat_map(&b, &a);
        assert_eq!(&heat[..3], &[0, 0, 0]);
        assert!(heat[15] > 0, "the differing pixel is red or brighter");
    }
}
