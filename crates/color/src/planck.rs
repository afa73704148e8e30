//! The Planckian (black-body) locus and correlated colour temperature.
//!
//! [`planckian_xyz`] integrates Planck's law against the 1 nm colour-matching functions from
//! 360 to 830 nm with a plain rectangular sum (471 terms), exactly as colour-science's
//! `CCT_to_uv_Planck1900` does with the full table, so the two agree to rounding (~1e-15).
//! [`krystek_uv`] is the fast rational approximation of Krystek (1985): two rational
//! polynomials instead of 471 exponentials, and within [`KRYSTEK_MAX_ERROR_UV`] of the
//! integral in CIE 1960 uv over its range 1000..=15000 K (measured by the test
//! `krystek_error_is_as_stated`).
//!
//! The correlated colour temperature of a chromaticity ([`cct`]) is the temperature of the
//! nearest locus point in the CIE 1960 uv plane (CIE 015), found on the integrated locus
//! by a table search in mireds followed by golden-section refinement; its signed distance
//! Duv is positive above the locus (towards green), as in ANSI C78.377 and colour-science.

use std::sync::OnceLock;

use super::cie::{uv1960_to_xy, xy_to_uv1960, xyz_to_xyy};
use super::cmf::{Observer, FIRST_NM};

/// First radiation constant for spectral radiance, c1 = 2 pi h c^2, in W m^2.
pub const C1: f64 = 3.741_771e-16;
/// Second radiation constant, c2 = h c / k, in m K.
pub const C2: f64 = 1.4388e-2;

/// Spectral radiant exitance of a black body at `kelvin` and wavelength `metres`
/// (refractive index 1), in W m^-3.
#[must_use]
pub fn planck_law(metres: f64, kelvin: f64) -> f64 {
    C1 / (metres.powi(5) * libm::expm1(C2 / (metres * kelvin)))
}

/// Tristimulus values of a black body at `kelvin`, normalised to Y = 1.
#[must_use]
pub fn planckian_xyz(kelvin: f64, observer: Observer) -> [f64; 3] {
    let mut sum = [0.0f64; 3];
    for (i, cmf) in observer.table().iter().enumerate() {
        let nm = f64::from(FIRST_NM) + i as f64;
        let s = planck_law(nm * 1e-9, kelvin);
        for k in 0..3 {
            sum[k] += s * cmf[k];
        }
    }
    if sum[1] > 0.0 && sum[1].is_finite() {
        sum.map(|v| v / sum[1])
    } else {
        [0.0; 3]
    }
}

/// Chromaticity xy of a black body at `kelvin` (CIE 1931 observer).
#[must_use]
pub fn planckian_xy(kelvin: f64) -> [f64; 2] {
    let [x, y, _] = xyz_to_xyy(planckian_xyz(kelvin, Observer::Cie1931));
    [x, y]
}

/// CIE 1960 uv of a black body at `kelvin` (CIE 1931 observer).
#[must_use]
pub fn planckian_uv(kelvin: f64) -> [f64; 2] {
    xy_to_uv1960(planckian_xy(kelvin))
}

/// Largest distance in CIE 1960 uv between [`krystek_uv`] and [`planckian_uv`] over
/// 1000..=15000 K (the worst case is near 5060 K: Krystek fitted an older table).
pub const KRYSTEK_MAX_ERROR_UV: f64 = 1.4e-4;

/// Krystek's (1985) rational approximation of the Planckian locus in CIE 1960 uv, for
/// 1000..=15000 K.
#[must_use]
pub fn krystek_uv(kelvin: f64) -> [f64; 2] {
    let t = kelvin;
    let u = (0.860_117_757 + 1.541_182_54e-4 * t + 1.286_412_12e-7 * t * t)
        / (1.0 + 8.424_202_35e-4 * t + 7.081_451_63e-7 * t * t);
    let v = (0.317_398_726 + 4.228_062_45e-5 * t + 4.204_816_91e-8 * t * t)
        / (1.0 - 2.897_418_16e-5 * t + 1.614_560_53e-7 * t * t);
    [u, v]
}

/// Chromaticity of the CIE daylight locus at `kelvin` (4000..=25000 K; CIE 015 eq. 3.3).
#[must_use]
pub fn daylight_xy(kelvin: f64) -> [f64; 2] {
    let t = kelvin;
    let x = if t <= 7000.0 {
        0.244_063 + 0.099_11e3 / t + 2.9678e6 / (t * t) - 4.6070e9 / (t * t * t)
    } else {
        0.237_040 + 0.247_48e3 / t + 1.9018e6 / (t * t) - 2.0064e9 / (t * t * t)
    };
    [x, -3.0 * x * x + 2.87 * x - 0.275]
}

/// Largest distance from the locus, in CIE 1960 uv, for which [`cct`] answers.
pub const CCT_MAX_DUV: f64 = 0.05;

/// Lowest temperature [`cct`] searches, in K.
pub const CCT_MIN_K: f64 = 1000.0;
/// Highest temperature [`cct`] searches, in K.
pub const CCT_MAX_K: f64 = 100_000.0;

/// The locus sampled every mired from 1e6 / [`CCT_MAX_K`] to 1e6 / [`CCT_MIN_K`].
fn mired_table() -> &'static [(f64, [f64; 2])] {
    static TABLE: OnceLock<Vec<(f64, [f64; 2])>> = OnceLock::new();
    TABLE.get_or_init(|| {
        let (lo, hi) = (1e6 / CCT_MAX_K, 1e6 / CCT_MIN_K);
        let n = (hi - lo).round() as usize;
        (0..=n)
            .map(|i| {
                let mired = lo + (hi - lo) * i as f64 / n as f64;
                (mired, planckian_uv(1e6 / mired))
            })
            .collect()
    })
}

fn dist2(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
}

/// Correlated colour temperature and Duv of chromaticity `xy` (CIE 1931 observer):
/// `Some((kelvin, duv))`, or `None` if `xy` is not finite, its nearest locus point lies at
/// an end of [`CCT_MIN_K`]..=[`CCT_MAX_K`], or it is farther than [`CCT_MAX_DUV`] from the
/// locus (CIE 015: a colour temperature means nothing that far from it).
/// Accurate to better than 0.01 K on the locus (see the tests).
#[must_use]
pub fn cct(xy: [f64; 2]) -> Option<(f64, f64)> {
    if !(xy[0].is_finite() && xy[1].is_finite()) {
        return None;
    }
    let uv = xy_to_uv1960(xy);
    let table = mired_table();
    let best = (0..table.len())
        .min_by(|&a, &b| dist2(table[a].1, uv).total_cmp(&dist2(table[b].1, uv)))?;
    if best == 0 || best == table.len() - 1 {
        return None;
    }
    // Golden-section search on the mired interval around the nearest sample.
    let f = |mired: f64| dist2(planckian_uv(1e6 / mired), uv);
    let (mut a, mut b) = (table[best - 1].0, table[best + 1].0);
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..48 {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d);
        }
    }
    let mired = (a + b) / 2.0;
    let kelvin = 1e6 / mired;
    let on = planckian_uv(kelvin);
    let distance = dist2(on, uv).sqrt();
    // Sign: positive on the side of the locus's upward normal (towards larger v).
    let tangent = locus_tangent(kelvin);
    let normal = [-tangent[1], tangent[0]];
    let normal = if normal[1] < 0.0 {
        [-normal[0], -normal[1]]
    } else {
        normal
    };
    let side = (uv[0] - on[0]) * normal[0] + (uv[1] - on[1]) * normal[1];
    (distance <= CCT_MAX_DUV).then_some((kelvin, distance.copysign(side)))
}

/// Unit tangent of the locus in uv at `kelvin`, pointing towards higher temperature.
fn locus_tangent(kelvin: f64) -> [f64; 2] {
    let h = kelvin * 1e-4;
    let (a, b) = (planckian_uv(kelvin - h), planckian_uv(kelvin + h));
    let d = [b[0] - a[0], b[1] - a[1]];
    let len = libm::hypot(d[0], d[1]);
    [d[0] / len, d[1] / len]
}

/// The point at signed distance `duv` from the locus at `kelvin`, along the locus's normal
/// in CIE 1960 uv (positive = above, towards green), as xy. The segment between
/// `duv = -0.05` and `0.05` is the iso-temperature line of a chromaticity diagram.
#[must_use]
pub fn iso_temperature_xy(kelvin: f64, duv: f64) -> [f64; 2] {
    let on = planckian_uv(kelvin);
    let t = locus_tangent(kelvin);
    let mut n = [-t[1], t[0]];
    if n[1] < 0.0 {
        n = [-n[0], -n[1]];
    }
    uv1960_to_xy([on[0] + duv * n[0], on[1] + duv * n[1]])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Illuminant, Observer};

    fn max_krystek_error() -> (f64, f64) {
        (1000..=15000)
            .step_by(5)
            .map(|t| {
                let t = f64::from(t);
                (dist2(krystek_uv(t), planckian_uv(t)).sqrt(), t)
            })
            .fold((0.0, 0.0), |a, b| if b.0 > a.0 { b } else { a })
    }

    #[test]
    fn krystek_error_is_as_stated() {
        let (err, at) = max_krystek_error();
        assert!(err <= KRYSTEK_MAX_ERROR_UV, "{err:e} at {at} K");
        assert!(
            err > KRYSTEK_MAX_ERROR_UV / 2.0,
            "bound is not tight: {err:e} at {at} K"
        );
    }

    #[test]
    fn cct_of_illuminants_and_off_locus_points() {
        let d65 = Illuminant::D65.xy(Observer::Cie1931);
        let (t, duv) = cct(d65).unwrap();
        // CIE 015: D65 has a CCT of about 6504 K, slightly above the locus.
        assert!(
            (t - 6504.0).abs() < 2.0 && (duv - 0.0032).abs() < 2e-4,
            "{t} {duv}"
        );
        let (t, duv) = cct(Illuminant::A.xy(Observer::Cie1931)).unwrap();
        assert!((t - 2856.0).abs() < 2.0 && duv.abs() < 1e-4, "{t} {duv}");
        for (kelvin, offset) in [(2500.0, 0.02), (4000.0, -0.03), (9000.0, 0.01)] {
            let xy = iso_temperature_xy(kelvin, offset);
            let (t, duv) = cct(xy).unwrap();
            assert!((t - kelvin).abs() < 0.05 * kelvin / 1000.0, "{kelvin}: {t}");
            assert!((duv - offset).abs() < 1e-6, "{kelvin}: {duv}");
        }
        assert!(cct([f64::NAN, 0.3]).is_none());
        assert!(
            cct([0.1, 0.8]).is_none(),
            "far green is nowhere near the locus's range"
        );
    }

    #[test]
    fn locus_is_finite_at_the_extremes() {
        for t in [1.0, 100.0, 1e3, 1e5, 1e7] {
            let xy = planckian_xy(t);
            assert!(xy[0].is_finite() && xy[1].is_finite(), "{t}: {xy:?}");
        }
    }
}
