//! Irradiance from nine spherical-harmonic coefficients (Ramamoorthi & Hanrahan 2001, "An
//! Efficient Representation for Irradiance Environment Maps").
//!
//! Projection: `L_lm = ∫ L(ω) Y_lm(ω) dω` with the real basis below, in the environment's own
//! axes (x, y, z of the direction, +Y up; any axes work when projection and evaluation agree).
//! The radiance is taken as constant over each texel and every basis function is integrated
//! exactly over each texel's solid angle (products of closed-form integrals in θ and φ), so a
//! uniform environment projects to exactly `L00 = 2√π·c` and zero elsewhere, whatever the
//! resolution. Sums run in f64, per row in parallel, rows added in order (deterministic).
//!
//! Evaluation: `E(n) = Σ Â_l L_lm Y_lm(n)` with `Â = (π, 2π/3, π/4)`, which is the paper's
//! formula with `c1..c5` ([`SH_C1`]..[`SH_C5`]); negative results (ringing opposite a
//! sun) are set to 0.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::equirect::Plane;

// Normalisations of the real basis: Y00 = K0, Y1m = K1·(y, z, x), Y2,-2 / Y2,-1 / Y21 =
// K2·(xy, yz, xz), Y20 = K20·(3z² - 1), Y22 = K22·(x² - y²).
const K0: f64 = 0.282_094_791_773_878_14; // ½·sqrt(1/π)
const K1: f64 = 0.488_602_511_902_919_9; // sqrt(3/(4π))
const K2: f64 = 1.092_548_430_592_079_2; // ½·sqrt(15/π)
const K20: f64 = 0.315_391_565_252_520_05; // ¼·sqrt(5/π)
const K22: f64 = 0.546_274_215_296_039_6; // ¼·sqrt(15/π)

/// `c1 = (π/4)·K22` of Ramamoorthi & Hanrahan (0.429043 in the paper).
pub const SH_C1: f64 = 0.429_042_765_404_891_7;
/// `c2 = (π/3)·K1` (0.511664).
pub const SH_C2: f64 = 0.511_663_353_973_244_1;
/// `c3 = (3π/4)·K20` (0.743125 in the paper, which rounds up the last digit).
pub const SH_C3: f64 = 0.743_123_868_301_127_1;
/// `c4 = π·K0` (0.886227).
pub const SH_C4: f64 = 0.886_226_925_452_757_9;
/// `c5 = (π/4)·K20` (0.247708).
pub const SH_C5: f64 = 0.247_707_956_100_375_7;

/// Closed-form `∫ f(θ) sinθ dθ` over row `y` of `h` (θ from θ0 = πy/h to θ1 = π(y+1)/h) for
/// f = 1, cosθ, cos²θ, sinθ, sinθcosθ, sin²θ.
fn row_factors(y: usize, h: usize) -> [f64; 6] {
    use std::f64::consts::PI;
    let (t0, t1) = (PI * y as f64 / h as f64, PI * (y + 1) as f64 / h as f64);
    let (m0, m1) = (libm::cos(t0), libm::cos(t1));
    let r1 = m0 - m1;
    let rc = (m0 * m0 - m1 * m1) / 2.0;
    let rcc = (m0.powi(3) - m1.powi(3)) / 3.0;
    let rs = (t1 - t0) / 2.0 - (libm::sin(2.0 * t1) - libm::sin(2.0 * t0)) / 4.0;
    let rsc = (libm::sin(t1).powi(3) - libm::sin(t0).powi(3)) / 3.0;
    let rss = r1 - rcc;
    [r1, rc, rcc, rs, rsc, rss]
}

/// Closed-form `∫ g(φ) dφ` over column `x` of `w` (φ from 2π(x/w - ½) to 2π((x+1)/w - ½))
/// for g = 1, cosφ, sinφ, cos²φ, sin²φ, cosφ·sinφ.
fn column_factors(x: usize, w: usize) -> [f64; 6] {
    use std::f64::consts::PI;
    let p0 = 2.0 * PI * (x as f64 / w as f64 - 0.5);
    let p1 = 2.0 * PI * ((x + 1) as f64 / w as f64 - 0.5);
    let dp = p1 - p0;
    let s2 = (libm::sin(2.0 * p1) - libm::sin(2.0 * p0)) / 4.0;
    [
        dp,
        libm::sin(p1) - libm::sin(p0),
        libm::cos(p0) - libm::cos(p1),
        dp / 2.0 + s2,
        dp / 2.0 - s2,
        (libm::sin(p1).powi(2) - libm::sin(p0).powi(2)) / 2.0,
    ]
}

/// The exact integrals of the nine basis functions over one texel.
fn texel_integrals(r: &[f64; 6], c: &[f64; 6]) -> [f64; 9] {
    let [r1, rc, rcc, rs, rsc, rss] = *r;
    let [c1, cc, cs, ccc, css, ccs] = *c;
    [
        K0 * r1 * c1,
        K1 * rc * c1,
        K1 * rs * cs,
        K1 * rs * cc,
        K2 * rsc * cc,
        K2 * rsc * cs,
        K20 * (3.0 * rss * css - r1 * c1),
        K2 * rss * ccs,
        K22 * (rss * ccc - rcc * c1),
    ]
}

/// The nine radiance coefficients `L_lm` of `p`, in the order L00, L1-1 (y), L10 (z),
/// L11 (x), L2-2 (xy), L2-1 (yz), L20 (3z²-1), L21 (xz), L22 (x²-y²).
pub(super) fn project(p: &Plane) -> [DVec3; 9] {
    let columns: Vec<[f64; 6]> = (0..p.width).map(|x| column_factors(x, p.width)).collect();
    let rows: Vec<[DVec3; 9]> = (0..p.height)
        .into_par_iter()
        .map(|y| {
            let r = row_factors(y, p.height);
            let mut acc = [DVec3::ZERO; 9];
            for (x, c) in columns.iter().enumerate() {
                let l = p.texel(x, y).as_dvec3();
                for (a, w) in acc.iter_mut().zip(texel_integrals(&r, c)) {
                    *a += l * w;
                }
            }
            acc
        })
        .collect();
    let mut sum = [DVec3::ZERO; 9];
    for row in &rows {
        for (s, r) in sum.iter_mut().zip(row) {
            *s += *r;
        }
    }
    sum
}

/// Irradiance `E(n)` from the coefficients of [`project`] (rounded to f32); `n` need not be
/// unit length. Never negative.
pub(super) fn irradiance(sh: &[Vec3; 9], n: Vec3) -> Vec3 {
    let n = n.normalize_or_zero();
    let (x, y, z) = (n.x, n.y, n.z);
    let (c1, c2, c3, c4, c5) = (
        SH_C1 as f32,
        SH_C2 as f32,
        SH_C3 as f32,
        SH_C4 as f32,
        SH_C5 as f32,
    );
    let e = sh[0] * c4
        + (sh[3] * x + sh[1] * y + sh[2] * z) * (2.0 * c2)
        + (sh[4] * (x * y) + sh[5] * (y * z) + sh[7] * (x * z)) * (2.0 * c1)
        + sh[6] * (c3 * z * z - c5)
        + sh[8] * (c1 * (x * x - y * y));
    e.max(Vec3::ZERO)
}
