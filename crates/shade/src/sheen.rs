//! `KHR_materials_sheen`'s layer: the "Charlie" distribution and visibility of Estevez and
//! Kulla 2017 ("Production Friendly Microfacet Sheen BRDF"), as the extension's
//! specification writes them, with α = sheenRoughness²:
//!
//! - `D(h) = (2 + 1/α) sin(θ_h)^(1/α) / (2π)`;
//! - `V = 1 / ((1 + Λ(N·V) + Λ(N·L)) 4 (N·V)(N·L))` (at most 1, as the sample viewer
//!   clamps it), `Λ(c) = exp(l(c))` below c = 0.5 and
//!   `exp(2 l(0.5) - l(1 - c))` above, `l(x) = a / (1 + b x^c) + d x + e` with the five
//!   coefficients interpolated by `(1 - α)²` between the paper's fits;
//! - the layer's directional albedo `E(N·V, r) = ∫ D V (N·L) dω` (sheen colour white), which
//!   scales what lies beneath it: `1 - max(sheenColor) E` ([`albedo`]).
//!
//! The two terms are written in `microfacet` (the environment's sheen prefilter uses them
//! too), over [`Num`] like the rest of the lighting. The albedo table is computed by a
//! midpoint rule over the hemisphere and stored with the source (`sheen.bin`): no process
//! computes it. `stored_sheen_table_is_the_computed_one` (tests) recomputes it and
//! compares; `REPLACE=1 cargo test --release -p realist-shade stored_sheen_table` rewrites
//! it after a change to the formulas. Sheen roughness is clamped to at least
//! [`MIN_ROUGHNESS`] (at 0 the distribution is a delta at grazing half vectors).

use std::sync::OnceLock;

use crate::simd::Num;

pub use crate::microfacet::{charlie_d, charlie_v, MIN_SHEEN_ROUGHNESS as MIN_ROUGHNESS};

/// Table entries per side: N·V = i / (size - 1), roughness = j / (size - 1).
pub const TABLE_SIZE: usize = 32;

/// α of sheen roughness `r` (clamped to [`MIN_ROUGHNESS`]..1 first).
#[inline(always)]
#[must_use]
pub fn alpha<T: Num>(r: T) -> T {
    crate::microfacet::sheen_alpha(r)
}

/// The layer's reflection `D V (N·L)` per unit irradiance, white (times the sheen colour by
/// the caller), at `N·H`, `N·L`, `N·V` for α.
#[inline(always)]
#[must_use]
pub fn lobe<T: Num>(nh: T, nl: T, nv: T, alpha: T) -> T {
    charlie_d(nh, alpha) * charlie_v(nl, nv, alpha) * nl
}

/// `E(N·V, r)` by a midpoint rule over the hemisphere: `n` steps of N·L and `2n` of the
/// azimuth, in f64.
#[must_use]
pub fn integrate(nv: f64, r: f64, n: usize) -> f64 {
    let nv = nv.clamp(1e-3, 1.0);
    let a = alpha(r);
    let v = glam::DVec3::new((1.0 - nv * nv).sqrt(), 0.0, nv);
    let (dc, dp) = (1.0 / n as f64, std::f64::consts::PI / n as f64);
    let mut sum = 0.0;
    for i in 0..n {
        let cl = (i as f64 + 0.5) * dc;
        let sl = (1.0 - cl * cl).sqrt();
        for j in 0..2 * n {
            let phi = (j as f64 + 0.5) * dp;
            let l = glam::DVec3::new(sl * libm::cos(phi), sl * libm::sin(phi), cl);
            let h = (l + v).normalize();
            sum += lobe(h.z, cl, nv, a);
        }
    }
    // dω = d(cos θ) dφ.
    sum * dc * dp
}

/// The albedo table: `TABLE_SIZE`² entries, row j roughness j/(size-1), column i N·V =
/// i/(size-1), each by [`integrate`] with `n` steps.
#[must_use]
pub fn compute(n: usize) -> Vec<f32> {
    use rayon::prelude::*;
    let s = TABLE_SIZE;
    (0..s * s)
        .into_par_iter()
        .map(|k| {
            let (i, j) = (k % s, k / s);
            integrate(i as f64 / (s - 1) as f64, j as f64 / (s - 1) as f64, n) as f32
        })
        .collect()
}

/// Midpoint steps of the stored table (N·L; twice as many in azimuth).
pub const TABLE_STEPS: usize = 256;

/// The stored table (little-endian f32, [`compute`]`(`[`TABLE_STEPS`]`)`).
pub(crate) static STORED: &[u8] = include_bytes!("sheen.bin");

fn table() -> &'static [f32] {
    static TABLE: OnceLock<Vec<f32>> = OnceLock::new();
    TABLE.get_or_init(|| {
        let t: Vec<f32> = STORED
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        if t.len() == TABLE_SIZE * TABLE_SIZE && t.iter().all(|x| x.is_finite()) {
            t
        } else {
            compute(TABLE_STEPS)
        }
    })
}

/// `E(N·V, r)` from the stored table, bilinear, clamped to its edges (NaN reads entry 0).
#[must_use]
pub fn albedo(nv: f32, r: f32) -> f32 {
    let t = table();
    let s = TABLE_SIZE;
    let last = (s - 1) as f32;
    let (fx, fy) = (
        (nv.clamp(0.0, 1.0) * last).max(0.0),
        (r.clamp(0.0, 1.0) * last).max(0.0),
    );
    let (x0, y0) = ((fx as usize).min(s - 2), (fy as usize).min(s - 2));
    let (tx, ty) = (fx - x0 as f32, fy - y0 as f32);
    let at = |x: usize, y: usize| t[y * s + x];
    let top = at(x0, y0) + (at(x0 + 1, y0) - at(x0, y0)) * tx;
    let bottom = at(x0, y0 + 1) + (at(x0 + 1, y0 + 1) - at(x0, y0 + 1)) * tx;
    top + (bottom - top) * ty
}

/// The stored table's bytes for `table` ([`STORED`]'s format).
#[must_use]
pub fn to_bytes(table: &[f32]) -> Vec<u8> {
    table.iter().flat_map(|x| x.to_le_bytes()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stored_sheen_table_is_the_computed_one() {
        let fresh = compute(TABLE_STEPS);
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/sheen.bin");
        if std::env::var_os("REPLACE").is_some() {
            std::fs::write(&path, to_bytes(&fresh)).expect("write sheen.bin");
        }
        let stored: Vec<f32> = std::fs::read(&path)
            .expect("sheen.bin")
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        assert_eq!(
            stored.len(),
            fresh.len(),
            "REPLACE=1 rewrites {}",
            path.display()
        );
        let worst = stored
            .iter()
            .zip(&fresh)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max);
        assert!(worst < 1e-6, "stored table differs by {worst}");
    }

    #[test]
    fn the_midpoint_rule_has_converged() {
        // Doubling the steps moves no entry of a coarse sample of the table by more than
        // 1e-3 (what the stored table's resolution is worth).
        for (nv, r) in [
            (0.05, 0.3),
            (0.3, 0.07),
            (0.5, 0.5),
            (1.0, 1.0),
            (0.02, 1.0),
        ] {
            let (a, b) = (
                integrate(nv, r, TABLE_STEPS),
                integrate(nv, r, 2 * TABLE_STEPS),
            );
            assert!((a - b).abs() < 1e-3, "({nv}, {r}): {a} vs {b}");
        }
    }
}
