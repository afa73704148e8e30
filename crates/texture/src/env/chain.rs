//! The specular chain: [`SPECULAR_LEVELS`] equirect levels, level k holding for every
//! direction R the GGX-filtered radiance `∫ L·NL·D(h) dω / ∫ NL·D(h) dω` with N = V = R and
//! perceptual roughness `r_k = k/(SPECULAR_LEVELS-1)` (the quantity Sample Viewer's
//! `ibl_filtering.frag` estimates with `Σ L·NL / Σ NL` over GGX samples).
//!
//! Sizes: level 0 (r = 0) is the source area-resampled to the base size (at most
//! [`BASE_WIDTH`]×[`BASE_HEIGHT`], the source's own if smaller, aspect kept); level k is the
//! base halved [`LEVEL_SHIFT`]`[k]` times, but never below [`MIN_LEVEL`] (64 x 32, or the
//! base's size if smaller): 256, 256, 128, 64, 64, 64, 64 texels wide for a large source,
//! since a rougher lobe needs fewer texels (32 wide at r >= 5/6 cost 5 % of
//! the exact value, bilinear across the kink where a sun crosses the lobe's horizon).
//!
//! Filters ([`LEVEL_FILTER`]):
//! - r >= 1/3 (level 2 and up): direct summation of the integral over the base level
//!   area-resampled to twice the level's size, each texel weighted by `NL·D(h)·Ω` at its
//!   centre, over the whole hemisphere (GGX tails are long: 90° from a sun 6000 times the sky
//!   still adds a few per cent). Exact up to that resolution and free of sampling patterns.
//! - r = 1/6 (level 1, 256×128: summation would cost ~4·10⁹ products): GGX importance
//!   sampling with 256 Hammersley samples a texel and filtered importance sampling (Colbert
//!   & Křivánek, GPU Gems 3 ch. 20): each sample reads a box-filtered pyramid of the
//!   full-resolution source (`resample.rs`) trilinearly at `lod = ½·log2(Ωs/Ωp) + 1`,
//!   `Ωs = 1/(n·pdf)`, `pdf = D/4` (N = V), `Ωp = (2π/W)(π/H)·sinθ` the source texel's solid
//!   angle at the sample's latitude, so a small bright sun spreads over about four samples'
//!   solid angle instead of making fireflies. The +1 (Colbert's and Babylon.js's bias; Sample
//!   Viewer's cube-map formula omits 4π, ~1.8 levels blurrier) is what turns the sky's sun
//!   into a round highlight: without it, or with 128 samples and +0.5, the highlight is a
//!   lumpy pattern of the sample set. Its footprint tracks the sample spacing, so near a sun
//!   the error does not fall with more samples (±20-30 % of the exact value 10° from the
//!   sky's sun with 256 to 8192 samples).
//!
//! Both filters exploit the equirect's symmetry: all texels of a row see the same lobe turned
//! about +Y, which only shifts u, so the taps or weights are computed once a row (for texel
//! 0) and shifted along it. Every output texel is a fixed sequential sum and rows are
//! independent, so the result is bit-identical for any number of threads.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::equirect::{dir_to_uv, texel_dir, texel_dir_f64, Plane};
use super::ggx;
use super::resample::{resample, Pyramid};

/// Levels in the specular chain; level k is for perceptual roughness `k/(SPECULAR_LEVELS-1)`.
pub const SPECULAR_LEVELS: usize = 7;
/// Largest level-0 width, in texels.
pub(super) const BASE_WIDTH: usize = 256;
/// Largest level-0 height, in texels.
pub(super) const BASE_HEIGHT: usize = 128;
/// Halvings of the base size per level.
pub(super) const LEVEL_SHIFT: [u32; SPECULAR_LEVELS] = [0, 0, 1, 2, 2, 2, 2];
/// The smallest summed level of a small source (base under [`BASE_WIDTH`] wide): halving
/// its base left the rough levels 16 x 8 texels for a 64 x 32 image, and the bilinear read
/// of a level that coarse spread a sun of a few texels over 22 degrees, up to 42 levels
/// off (mean 4.9) on rough surfaces; split to at least 128 x 64, within 2 (mean 0.2):
/// `small_sun_in_a_small_image_within_two_levels`. A large source keeps 64 x 32 levels:
/// 128 x 64 ones over its 256 x 128 base cost 2.5 times the prefilter time (200 to 520 ms).
pub(super) const MIN_LEVEL: (usize, usize) = (128, 64);

/// How a level of the chain is computed (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum LevelFilter {
    /// The source area-resampled (r = 0).
    Resampled,
    /// GGX importance sampling with `samples` Hammersley samples a texel, filtered at the
    /// level of detail `½·log2(Ωs/Ωp) + lod_bias`.
    Sampled { samples: u32, lod_bias: f32 },
    /// Direct summation over the base level resampled to `scale` times the level's size.
    Summed { scale: usize },
}

impl LevelFilter {
    /// Two words for the cache key.
    pub(super) fn key(self) -> [u64; 2] {
        match self {
            LevelFilter::Resampled => [0, 0],
            LevelFilter::Sampled { samples, lod_bias } => {
                [1 << 32 | u64::from(samples), u64::from(lod_bias.to_bits())]
            }
            LevelFilter::Summed { scale } => [2, scale as u64],
        }
    }
}

/// The filter of every level.
pub(super) const LEVEL_FILTER: [LevelFilter; SPECULAR_LEVELS] = [
    LevelFilter::Resampled,
    LevelFilter::Sampled {
        samples: 256,
        lod_bias: 1.0,
    },
    LevelFilter::Summed { scale: 2 },
    LevelFilter::Summed { scale: 2 },
    LevelFilter::Summed { scale: 2 },
    LevelFilter::Summed { scale: 2 },
    LevelFilter::Summed { scale: 2 },
];

/// The (width, height) of every chain level for a `width×height` source.
pub(super) fn level_dims(width: usize, height: usize) -> [(usize, usize); SPECULAR_LEVELS] {
    let scale = 1f64
        .min(BASE_WIDTH as f64 / width as f64)
        .min(BASE_HEIGHT as f64 / height as f64);
    let side = |s: usize| ((s as f64 * scale).round() as usize).clamp(1, s);
    let (bw, bh) = (side(width), side(height));
    let mut k = 0;
    LEVEL_SHIFT.map(|s| {
        let summed = matches!(LEVEL_FILTER[k], LevelFilter::Summed { .. });
        k += 1;
        if summed && bw < BASE_WIDTH {
            // A small source: its summed levels keep at least its own size, its texels
            // each split into f x f (`summed_level`) up to MIN_LEVEL, the same
            // piecewise-constant radiance summed more finely.
            let f = MIN_LEVEL
                .0
                .div_ceil(bw)
                .max(MIN_LEVEL.1.div_ceil(bh))
                .max(1);
            (bw * f, bh * f)
        } else {
            ((bw >> s).max(1), (bh >> s).max(1))
        }
    })
}

/// Levels of the sheen chain: level k holds, for every direction N (= V), the radiance
/// averaged over the `KHR_materials_sheen` lobe `D·V·NL` of sheen roughness
/// `k/(SHEEN_LEVELS-1)` (clamped as the shading clamps it), which the `pbr` mode multiplies
/// by the sheen colour and its directional albedo (the sample viewer prefilters a
/// "Charlie" environment for the same purpose).
pub const SHEEN_LEVELS: usize = 4;
/// The size of every sheen level (the lobe is broad: its half-width is tens of degrees).
pub(super) const SHEEN_DIMS: (usize, usize) = (32, 16);

/// The (width, height) of every stored level: the specular chain's ([`level_dims`]), then
/// the sheen chain's.
pub(super) fn all_dims(width: usize, height: usize) -> Vec<(usize, usize)> {
    let mut d = level_dims(width, height).to_vec();
    d.extend([SHEEN_DIMS; SHEEN_LEVELS]);
    d
}

/// The sheen chain over the chain's `base` level (area-resampled to twice the levels' size,
/// a small base's texels first split to reach it).
fn sheen_levels(base: &Plane) -> Vec<Plane> {
    let (w, h) = (2 * SHEEN_DIMS.0, 2 * SHEEN_DIMS.1);
    let big = split(
        base,
        w.div_ceil(base.width.max(1)),
        h.div_ceil(base.height.max(1)),
    );
    let fine = resample(&big, w, h);
    (0..SHEEN_LEVELS)
        .map(|k| {
            let alpha = crate::microfacet::sheen_alpha(k as f64 / (SHEEN_LEVELS - 1) as f64);
            let lobe = move |nl: f64, nh: f64| {
                crate::microfacet::charlie_d(nh, alpha)
                    * crate::microfacet::charlie_v(nl, 1.0, alpha)
            };
            summed_with(&fine, 2, SHEEN_DIMS, &lobe)
        })
        .collect()
}

/// The chain of `src`: the specular levels, then the sheen levels ([`all_dims`]).
pub(super) fn build(src: &Plane) -> Vec<Plane> {
    let dims = level_dims(src.width, src.height);
    let base = resample(src, dims[0].0, dims[0].1);
    let pyramid = Pyramid::new(src);
    let omega_p0 = (2.0 * std::f64::consts::PI / src.width as f64)
        * (std::f64::consts::PI / src.height as f64);
    let last = (SPECULAR_LEVELS - 1) as f64;
    let mut levels = Vec::with_capacity(SPECULAR_LEVELS);
    for (k, (filter, d)) in LEVEL_FILTER.iter().zip(dims).enumerate() {
        let r = k as f64 / last;
        levels.push(match *filter {
            LevelFilter::Resampled => resample(&base, d.0, d.1),
            LevelFilter::Sampled { samples, lod_bias } => sampled_level(
                &pyramid,
                omega_p0 / libm::pow(4f64, f64::from(lod_bias)),
                r,
                samples,
                d,
            ),
            LevelFilter::Summed { scale } => summed_level(&base, r, scale, d),
        });
    }
    levels.extend(sheen_levels(&base));
    levels
}

/// One GGX sample of a level in the frame N = V = +Z.
struct LobeSample {
    l: Vec3,
    nl: f32,
    /// `½·log2(Ωs/Ωp0)`, Ωp0 the source texel's solid angle at the equator (divided by 4 per
    /// level of bias).
    lod_bias: f32,
}

/// The samples of roughness `r` (those with NL > 0) and the sum of their NL.
fn lobe(r: f64, n: u32, omega_p0: f64) -> (Vec<LobeSample>, f32) {
    let alpha = ggx::alpha(r);
    let mut samples = Vec::with_capacity(n as usize);
    let mut weight = 0.0;
    for i in 0..n {
        let h = ggx::sample_h(ggx::hammersley(i, n), alpha);
        let l = 2.0 * h.z * h - DVec3::Z;
        if l.z <= 0.0 {
            continue;
        }
        let pdf = ggx::d(h.z, alpha) / 4.0;
        let omega_s = 1.0 / (f64::from(n) * pdf);
        samples.push(LobeSample {
            l: l.as_vec3(),
            nl: l.z as f32,
            lod_bias: (0.5 * libm::log2(omega_s / omega_p0)) as f32,
        });
        weight += l.z;
    }
    (samples, weight as f32)
}

/// One level of the chain by filtered importance sampling: the lobe of roughness `r` around
/// every texel direction. `omega_p0` is the source texel's solid angle at the equator,
/// divided by `4^bias` for a lod bias.
///
/// All texels of a row see the same lobe turned about +Y, which only shifts u: the taps
/// (u, v, lod, weight) are computed once a row, for texel 0 in the frame
/// `any_orthonormal_pair` gives its direction, and texel x reads them at `u + x/w`.
fn sampled_level(pyramid: &Pyramid, omega_p0: f64, r: f64, n: u32, dims: (usize, usize)) -> Plane {
    let (w, h) = dims;
    let (samples, weight) = lobe(r, n, omega_p0);
    let inv = if weight > 0.0 { 1.0 / weight } else { 0.0 };
    let mut rgb = vec![0.0f32; 3 * w * h];
    rgb.par_chunks_mut(3 * w).enumerate().for_each(|(y, row)| {
        let n0 = texel_dir(0, y, w, h);
        let (t, b) = n0.any_orthonormal_pair();
        let mut taps = Vec::with_capacity(2 * samples.len());
        for s in &samples {
            let l = t * s.l.x + b * s.l.y + n0 * s.l.z;
            // Ωp = Ωp0·sinθ: ½·log2(1/sinθ) = -¼·log2(1 - y²).
            let lod = s.lod_bias - 0.25 * libm::log2f((1.0 - l.y * l.y).max(1e-12));
            pyramid.push_taps(dir_to_uv(l), lod, s.nl * inv, &mut taps);
        }
        for (x, out) in row.chunks_exact_mut(3).enumerate() {
            let sum = Pyramid::sum_taps(&taps, x as f32 / w as f32);
            out.copy_from_slice(&sum.to_array());
        }
    });
    Plane {
        width: w,
        height: h,
        rgb,
    }
}

/// `p` with each texel split into `fx` x `fy` texels of the same radiance.
fn split(p: &Plane, fx: usize, fy: usize) -> Plane {
    let (fx, fy) = (fx.max(1), fy.max(1));
    let (w, h) = (p.width * fx, p.height * fy);
    let mut rgb = Vec::with_capacity(3 * w * h);
    for y in 0..h {
        for x in 0..w {
            rgb.extend(p.texel(x / fx, y / fy).to_array());
        }
    }
    Plane {
        width: w,
        height: h,
        rgb,
    }
}

/// One level by direct summation over `base` resampled to `scale`× the level's size (or
/// the largest multiple `base` allows): output texel x of a row is `Σ w·L` over the coarse
/// texels with the row's weights (NL > 0 only) shifted by `m·x` columns.
fn summed_level(base: &Plane, r: f64, scale: usize, dims: (usize, usize)) -> Plane {
    let alpha = ggx::alpha(r);
    summed_with(base, scale, dims, &|_, nh| ggx::d(nh, alpha))
}

/// [`summed_level`] with the lobe `lobe(NL, NH)` (each texel weighted by `NL·lobe·Ω`).
fn summed_with(
    base: &Plane,
    scale: usize,
    dims: (usize, usize),
    lobe: &(dyn Fn(f64, f64) -> f64 + Sync),
) -> Plane {
    let (w, h) = dims;
    let m = (1..=scale.max(1))
        .rev()
        .find(|m| m * w <= base.width && m * h <= base.height)
        .unwrap_or(1);
    let coarse = if w > base.width || h > base.height {
        // Larger than a small base (`level_dims`): each base texel split into the level's
        // texels it covers (whole multiples), the same radiance.
        split(base, w / base.width.max(1), h / base.height.max(1))
    } else {
        resample(base, m * w, m * h)
    };
    let (cw, ch) = (coarse.width, coarse.height);
    let dirs: Vec<DVec3> = (0..ch)
        .flat_map(|j| (0..cw).map(move |i| texel_dir_f64(i, j, cw, ch)))
        .collect();
    let omega: Vec<f64> = (0..ch)
        .map(|j| {
            let t = |j: usize| libm::cos(std::f64::consts::PI * j as f64 / ch as f64);
            2.0 * std::f64::consts::PI / cw as f64 * (t(j) - t(j + 1))
        })
        .collect();
    let mut rgb = vec![0.0f32; 3 * w * h];
    rgb.par_chunks_mut(3 * w).enumerate().for_each(|(y, row)| {
        let n = texel_dir_f64(0, y, w, h);
        let mut weights: Vec<(usize, usize, f64)> = Vec::new();
        for (idx, c) in dirs.iter().enumerate() {
            let nl = n.dot(*c);
            if nl > 0.0 {
                let nh = (n + *c).normalize().dot(n);
                weights.push((idx % cw, idx / cw, nl * lobe(nl, nh) * omega[idx / cw]));
            }
        }
        let total: f64 = weights.iter().map(|w| w.2).sum();
        let inv = if total > 0.0 { 1.0 / total } else { 0.0 };
        let weights: Vec<(usize, usize, f32)> = weights
            .into_iter()
            .map(|(i, j, wt)| (i, j, (wt * inv) as f32))
            .collect();
        for (x, out) in row.chunks_exact_mut(3).enumerate() {
            let shift = m * x;
            let mut acc = Vec3::ZERO;
            for &(i, j, wt) in &weights {
                let i = if i + shift >= cw {
                    i + shift - cw
                } else {
                    i + shift
                };
                acc += coarse.texel(i, j) * wt;
            }
            out.copy_from_slice(&acc.to_array());
        }
    });
    Plane {
        width: w,
        height: h,
        rgb,
    }
}
