//! The environment-independent half of the split sum: for each (NV, r) the scale `A` of F0
//! and the bias `B`, so that `∫ F·D·Vis·NL dω ≈ F0·A + f90·B` (Karis 2013; Sample Viewer's
//! `ibl_filtering.frag`). With `V = (sqrt(1-NV²), 0, NV)`, N = +Z, GGX half vectors from
//! [`LUT_SAMPLES`] Hammersley points, `L = 2(V·H)H - V`, `Fc = (1-VH)^5`,
//! `g = Vis·VH·NL/NH` over NL > 0: `A = (4/n)Σ(1-Fc)g`, `B = (4/n)Σ Fc·g`, summed in f64.
//!
//! Layout: [`LUT_SIZE`]² entries; row j is r = j/(size-1), column i is NV = i/(size-1)
//! (NV clamped to [`NV_MIN`] when computing), so both ends of both axes are table points and
//! [`BrdfLut::lookup`] is bilinear, clamped. `A + B = Ess`, the single-scattering directional
//! albedo of white metal: 1 - ln 2 head-on at r = 1, → 1 as r → 0.
//! Beside `(A, B)` each entry holds [`BrdfLut::lookup_ess`]'s `E_c`: `A + B` read the way
//! three.js reads its 16 x 16 DFG table, at texel centres (N·V and r clamped to
//! [[`THREE_MIN`], 1 - [`THREE_MIN`]]). The punctual lights' multiple-scattering
//! compensation uses it, so a rough metal under a lamp agrees with three.js (roughness 1
//! compensates as roughness 0.969 does: head-on 1/0.345 instead of 1/0.307; with the exact
//! value the sphere of `tests/threejs.rs` was 7 levels brighter than three's at its centre).
//! The environment's split sum keeps the exact `(A, B)`, so the white furnace stays white.
//! Stored with the source (`lut.bin`, checked against a fresh computation by a test). 8192 samples an entry:
//! with 1024, the sampling error in A reached 9e-3 at grazing NV (measured against a
//! quadrature in `tests.rs`); with 8192 the table is within 2.4e-3 of it.

use std::sync::OnceLock;

use glam::DVec3;
use rayon::prelude::*;

use super::ggx;

/// Entries a side.
pub const LUT_SIZE: usize = 64;
/// Hammersley samples per entry.
pub const LUT_SAMPLES: u32 = 8192;
/// Smallest NV computed (grazing V has NV = 0).
pub const NV_MIN: f64 = 1e-3;
/// The lowest table coordinate three.js's 16-texel DFG table reaches (half a texel).
pub const THREE_MIN: f32 = 1.0 / 32.0;

/// The split-sum table (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct BrdfLut {
    size: usize,
    /// `(A, B)`, row-major, rows by roughness.
    ab: Vec<[f32; 2]>,
    /// `E_c` of each entry ([`BrdfLut::lookup_ess`]), from `ab`.
    ec: Vec<f32>,
}

/// The GGX half vectors of roughness `r` for `n` Hammersley points (N = +Z).
pub(super) fn half_vectors(r: f64, n: u32) -> Vec<DVec3> {
    let alpha = ggx::alpha(r);
    (0..n.max(1))
        .map(|i| ggx::sample_h(ggx::hammersley(i, n.max(1)), alpha))
        .collect()
}

/// `(A, B)` at (NV, r) by importance sampling over the half vectors `hs` of
/// [`half_vectors`]`(r, n)`.
pub(super) fn split_sum(nv: f64, r: f64, hs: &[DVec3]) -> (f64, f64) {
    let nv = nv.clamp(NV_MIN, 1.0);
    let alpha = ggx::alpha(r);
    let v = DVec3::new((1.0 - nv * nv).sqrt(), 0.0, nv);
    let (mut a, mut b) = (0.0, 0.0);
    for &h in hs {
        let vh = v.dot(h);
        let l = 2.0 * vh * h - v;
        let (nl, nh) = (l.z, h.z);
        if nl <= 0.0 || nh <= 0.0 || vh <= 0.0 {
            continue;
        }
        let g = ggx::vis(nl, nv, alpha) * vh * nl / nh;
        let fc = crate::microfacet::schlick_weight::<f64>(vh);
        a += (1.0 - fc) * g;
        b += fc * g;
    }
    let k = 4.0 / hs.len().max(1) as f64;
    (a * k, b * k)
}

impl BrdfLut {
    /// Computes a `size×size` table with `samples` samples per entry (`size >= 2`).
    #[must_use]
    pub fn compute(size: usize, samples: u32) -> Self {
        let size = size.max(2);
        let step = 1.0 / (size - 1) as f64;
        let mut ab = vec![[0.0f32; 2]; size * size];
        ab.par_chunks_mut(size).enumerate().for_each(|(j, row)| {
            let r = j as f64 * step;
            let hs = half_vectors(r, samples);
            for (i, e) in row.iter_mut().enumerate() {
                let (a, b) = split_sum(i as f64 * step, r, &hs);
                *e = [a as f32, b as f32];
            }
        });
        Self::with_ec(size, ab)
    }

    /// The table of `ab` with its `E_c` column filled in (module docs).
    fn with_ec(size: usize, ab: Vec<[f32; 2]>) -> Self {
        let mut lut = Self {
            size,
            ab,
            ec: vec![0.0; size * size],
        };
        let last = (size - 1) as f32;
        let clamp = |t: f32| t.clamp(THREE_MIN, 1.0 - THREE_MIN);
        let ec: Vec<f32> = (0..size * size)
            .map(|k| {
                let (i, j) = (k % size, k / size);
                let (a, b) = lut.lookup(clamp(i as f32 / last), clamp(j as f32 / last));
                a + b
            })
            .collect();
        lut.ec = ec;
        lut
    }

    /// Entries a side.
    #[must_use]
    pub fn size(&self) -> usize {
        self.size
    }

    /// `(A, B)` at `nv` = N·V and perceptual roughness `r`, both clamped to [0, 1],
    /// bilinear between table points.
    #[must_use]
    #[inline(always)]
    pub fn lookup(&self, nv: f32, r: f32) -> (f32, f32) {
        let (a, b, _) = self.lookup_ess(nv, r);
        (a, b)
    }

    /// [`BrdfLut::lookup`] and `E_c`, the single-scattering albedo the punctual lights'
    /// compensation uses (module docs), bilinear between table points like `(A, B)`.
    #[must_use]
    #[inline(always)]
    pub fn lookup_ess(&self, nv: f32, r: f32) -> (f32, f32, f32) {
        let last = (self.size - 1) as f32;
        let fx = nv.clamp(0.0, 1.0) * last;
        let fy = r.clamp(0.0, 1.0) * last;
        // Saturating casts: NaN reads entry 0.
        let (x0, y0) = (
            (fx as usize).min(self.size - 2),
            (fy as usize).min(self.size - 2),
        );
        let (tx, ty) = (fx - x0 as f32, fy - y0 as f32);
        let at = |x: usize, y: usize| {
            let k = y * self.size + x;
            let [a, b] = self.ab[k];
            glam::Vec3::new(a, b, self.ec[k])
        };
        let top = at(x0, y0).lerp(at(x0 + 1, y0), tx);
        let bottom = at(x0, y0 + 1).lerp(at(x0 + 1, y0 + 1), tx);
        let v = top.lerp(bottom, ty);
        (v.x, v.y, v.z)
    }

    /// [`BrdfLut::lookup_ess`] for eight points at once (the same values; NaN reads entry
    /// 0).
    #[must_use]
    #[inline(always)]
    pub fn lookup_ess_lanes<L: realist_simd::Level>(
        &self,
        nv: realist_simd::F8<L>,
        r: realist_simd::F8<L>,
    ) -> [realist_simd::F8<L>; 3] {
        super::lanes::table(self.size, &self.ab, &self.ec, nv, r)
    }
}

/// [`BrdfLut::compute`]`(`[`LUT_SIZE`]`, `[`LUT_SAMPLES`]`)`, stored with the source
/// (`lut.bin`: the `(A, B)` pairs row-major as little-endian f32): computing it cost every
/// process that shades `pbr` about 200 ms of CPU. `stored_table_is_the_computed_one`
/// (`tests.rs`) recomputes it and compares; `REPLACE=1 cargo test --release -p
/// realist-texture stored_table` rewrites the file after a change to the BRDF.
pub(super) static STORED: &[u8] = include_bytes!("lut.bin");

impl BrdfLut {
    /// The stored table ([`STORED`]); `None` if it is not a [`LUT_SIZE`]² table of finite
    /// values.
    #[must_use]
    pub fn stored() -> Option<Self> {
        let size = LUT_SIZE;
        if STORED.len() != size * size * 8 {
            return None;
        }
        let f = |c: &[u8]| f32::from_le_bytes([c[0], c[1], c[2], c[3]]);
        let ab: Vec<[f32; 2]> = STORED
            .chunks_exact(8)
            .map(|c| [f(&c[..4]), f(&c[4..])])
            .collect();
        ab.iter()
            .all(|e| e[0].is_finite() && e[1].is_finite())
            .then(|| Self::with_ec(size, ab))
    }

    /// The table as stored bytes ([`STORED`]'s format).
    #[must_use]
    pub fn to_bytes(&self) -> Vec<u8> {
        self.ab
            .iter()
            .flat_map(|e| e.iter().flat_map(|x| x.to_le_bytes()))
            .collect()
    }
}

/// The process-wide table: [`LUT_SIZE`]², [`LUT_SAMPLES`] samples, as stored (computed on
/// first use only if the stored one were unusable).
#[must_use]
pub fn brdf_lut() -> &'static BrdfLut {
    static LUT: OnceLock<BrdfLut> = OnceLock::new();
    LUT.get_or_init(|| BrdfLut::stored().unwrap_or_else(|| BrdfLut::compute(LUT_SIZE, LUT_SAMPLES)))
}
