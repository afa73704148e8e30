//! The colours inside the horseshoe: what each chromaticity "looks like" on an sRGB screen.
//!
//! Most chromaticities of the diagram lie outside the sRGB gamut, so any fill is a gamut
//! mapping. colour-science (and most plots) convert xy to linear sRGB, apply the transfer
//! curve to the unclipped values, divide by the largest component and clip ([`FillStyle::
//! ColourScience`], kept to reproduce their figures). Both the division by the *largest*
//! component and the clipping have kinks: where the largest channel changes (lines from the
//! white point towards yellow, cyan and magenta) and where a channel crosses zero (the
//! gamut's edges), the colour's gradient jumps, which shows as bright and dark ridges.
//!
//! [`FillStyle::Smooth`] (the default) is smooth everywhere, with no clipping at all:
//!
//! 1. xy -> XYZ (Y = 1) -> linear sRGB `c`, scaled by its 8-norm so the components are O(1).
//! 2. Desaturate towards white just enough to make every channel positive: add
//!    `w = softplus(-softmin(c))` of white, where softmin is a log-sum-exp soft minimum
//!    (never above the true minimum) and softplus(t) = (t + sqrt(t^2 + eps^2)) / 2 (never
//!    below t). So `c + w` is strictly positive, and in-gamut colours far from the edges
//!    are moved by at most eps / 2 plus the log-sum-exp's small bias.
//! 3. Divide by the 8-norm (a smooth stand-in for the maximum; it is >= the maximum, so
//!    every channel ends in (0, 1]), then encode with the sRGB curve.
//!
//! Adding white keeps each chromaticity on its line towards D65, so hue (dominant
//! wavelength) is kept and only saturation drops outside sRGB.

use crate::color::{srgb_encode, xy_to_xyz, RgbSpace};

/// How the inside of the spectral locus is coloured.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FillStyle {
    /// Smooth gamut mapping, no ridges (see the module docs).
    #[default]
    Smooth,
    /// colour-science's `normalise_maximum(XYZ_to_plotting_colourspace(...))` with clipping.
    ColourScience,
    /// No fill (white).
    None,
}

/// Steepness of the soft minimum (larger is closer to the true minimum).
const SOFTMIN_K: f64 = 24.0;
/// Width of the softplus knee.
const SOFTPLUS_EPS: f64 = 0.02;
/// Exponent of the norm used as a smooth maximum.
const SMOOTH_MAX_P: i32 = 8;

fn p_norm(c: [f64; 3]) -> f64 {
    let p = f64::from(SMOOTH_MAX_P);
    libm::pow(
        c.iter().map(|v| v.abs().powi(SMOOTH_MAX_P)).sum::<f64>(),
        1.0 / p,
    )
}

/// Linear sRGB (IEC matrix, as colour-science plots use) of chromaticity `xy` at Y = 1.
fn linear_srgb(space: &RgbSpace, xy: [f64; 2]) -> [f64; 3] {
    space.xyz_to_linear(xy_to_xyz(xy))
}

/// The smooth fill of `xy` as encoded sRGB in (0, 1] (see the module docs); black for `y <= 0`.
#[must_use]
pub fn smooth_fill(space: &RgbSpace, xy: [f64; 2]) -> [f64; 3] {
    smooth_fill_linear(space, xy).map(srgb_encode)
}

/// [`smooth_fill`] before the transfer curve: linear sRGB in [0, 1].
#[must_use]
pub fn smooth_fill_linear(space: &RgbSpace, xy: [f64; 2]) -> [f64; 3] {
    if xy[1].is_nan() || xy[1] <= 0.0 || !xy[0].is_finite() {
        return [0.0; 3];
    }
    let c = linear_srgb(space, xy);
    let n = p_norm(c);
    if n.is_nan() || n <= 0.0 || !n.is_finite() {
        return [0.0; 3];
    }
    let c = c.map(|v| v / n);
    let lse: f64 = libm::log(c.iter().map(|v| libm::exp(-SOFTMIN_K * v)).sum::<f64>());
    let softmin = -lse / SOFTMIN_K;
    let t = -softmin;
    let w = (t + (t * t + SOFTPLUS_EPS * SOFTPLUS_EPS).sqrt()) / 2.0;
    let lifted = c.map(|v| v + w);
    let m = p_norm(lifted);
    lifted.map(|v| v / m)
}

/// colour-science's fill of `xy`: encode the unclipped linear sRGB, divide by the largest
/// component, clip to [0, 1].
#[must_use]
pub fn colour_science_fill(space: &RgbSpace, xy: [f64; 2]) -> [f64; 3] {
    let enc = colour_science_unclipped(space, xy);
    let max = enc[0].max(enc[1]).max(enc[2]);
    if max.is_nan() || max <= 0.0 {
        return [0.0; 3];
    }
    enc.map(|v| (v / max).clamp(0.0, 1.0))
}

/// The encoded but unclipped sRGB of `xy` at Y = 1 (negative values stay on the linear
/// segment of the curve).
#[must_use]
pub fn colour_science_unclipped(space: &RgbSpace, xy: [f64; 2]) -> [f64; 3] {
    linear_srgb(space, xy).map(srgb_encode)
}

/// The fill of `xy` in `style` as encoded sRGB in [0, 1].
#[must_use]
pub fn fill(style: FillStyle, space: &RgbSpace, xy: [f64; 2]) -> [f64; 3] {
    match style {
        FillStyle::Smooth => smooth_fill(space, xy),
        FillStyle::ColourScience => colour_science_fill(space, xy),
        FillStyle::None => [1.0; 3],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The largest jump of the second difference of the fill along a circle of `radius`
    /// around D65, relative to the step: a kink shows as a spike.
    fn max_second_difference(style: FillStyle, radius: f64) -> f64 {
        let space = RgbSpace::srgb();
        let n = 4000;
        let at = |i: i32| {
            let a = f64::from(i) / f64::from(n) * std::f64::consts::TAU;
            fill(
                style,
                &space,
                [
                    0.3127 + radius * libm::cos(a),
                    0.3290 + radius * libm::sin(a),
                ],
            )
        };
        (0..n)
            .map(|i| {
                let (a, b, c) = (at(i - 1), at(i), at(i + 1));
                (0..3)
                    .map(|k| (a[k] - 2.0 * b[k] + c[k]).abs())
                    .fold(0.0, f64::max)
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn smooth_fill_has_no_ridges_where_colour_science_has_them() {
        for radius in [0.05, 0.15, 0.3] {
            let smooth = max_second_difference(FillStyle::Smooth, radius);
            let cs = max_second_difference(FillStyle::ColourScience, radius);
            // A kink gives a second difference of order of the step (1.6e-3 rad); smooth
            // curves give its square.
            assert!(smooth < 2e-4, "radius {radius}: smooth {smooth:e}");
            assert!(
                cs > 5.0 * smooth,
                "radius {radius}: colour-science {cs:e} vs {smooth:e}"
            );
        }
    }

    #[test]
    fn smooth_fill_stays_in_range_and_keeps_hue_order() {
        let space = RgbSpace::srgb();
        for i in 0..=100 {
            for j in 1..=100 {
                let xy = [f64::from(i) / 100.0 * 0.8, f64::from(j) / 100.0 * 0.9];
                let c = smooth_fill(&space, xy);
                assert!(
                    c.iter().all(|v| v.is_finite() && (0.0..=1.0).contains(v)),
                    "{xy:?} {c:?}"
                );
            }
        }
        let red = smooth_fill(&space, [0.64, 0.33]);
        let green = smooth_fill(&space, [0.30, 0.60]);
        let blue = smooth_fill(&space, [0.15, 0.06]);
        assert!(red[0] > 0.95 && red[1] < 0.3 && red[2] < 0.3, "{red:?}");
        assert!(
            green[1] > 0.95 && green[0] < 0.3 && green[2] < 0.3,
            "{green:?}"
        );
        assert!(blue[2] > 0.95 && blue[0] < 0.3 && blue[1] < 0.3, "{blue:?}");
        let white = smooth_fill(&space, [0.3127, 0.3290]);
        assert!(white.iter().all(|&v| v > 0.9), "{white:?}");
        assert_eq!(smooth_fill(&space, [0.3, 0.0]), [0.0; 3]);
        assert_eq!(smooth_fill(&space, [f64::NAN, 0.3]), [0.0; 3]);
    }
}
