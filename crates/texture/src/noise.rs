//! Deterministic 3D gradient noise: Ken Perlin's "improved noise" (SIGGRAPH 2002), with
//! fractal sums (fBm, turbulence) that are band-limited by a filter width.
//!
//! # Noise
//!
//! [`perlin`] is the reference algorithm exactly: Perlin's own permutation table, the
//! quintic fade `6t^5 - 15t^4 + 10t^3` (C2 across lattice cells) and his twelve edge
//! gradients, so `perlin(3.14, 42, 7)` is his published 0.13691995878400012. It is computed
//! in f64, so coordinates keep their fraction up to about 2^40 (f32 would lose it at 2^16).
//! The value is 0 at every lattice point, continuous with continuous first and second
//! derivatives, and within `[-NOISE_BOUND, NOISE_BOUND]` ([`NOISE_BOUND`] is the known
//! maximum of this gradient set, slightly above 1). The lattice repeats every 256 units.
//! A non-finite coordinate gives 0 (the mean), never NaN.
//!
//! Rejected: a crate (`noise`, `bracket-noise`): the algorithm is 40 lines, a dependency
//! would pin its own table and float type, and the reference value pins ours. Simplex noise
//! is cheaper in high dimensions but has no single reference table; in 3D the cost is close.
//!
//! # Fractal sums and band limiting
//!
//! [`fbm`] sums `octaves` copies of the noise at frequencies `LACUNARITY^i` with amplitudes
//! `GAIN^i`, normalised by the sum of all amplitudes so the result stays in about `[-1, 1]`
//! whatever the octave count; [`turbulence`] sums `|noise|` the same way (in `[0, 1]`).
//! Octave `i` is shifted by an irrational offset so the octaves do not all vanish at the
//! origin.
//!
//! Frequency clamping (Ebert et al., *Texturing and Modeling*, ch. 2): a sample that stands
//! for a filter footprint `width` units wide cannot represent features smaller than about
//! two footprints. An octave of frequency `f` is kept whole while `f * width <=
//! FADE_START`, dropped from `f * width >= FADE_END`, and faded smoothly in between; a
//! dropped octave contributes its mean (0 for fBm, [`MEAN_ABS_NOISE`] for turbulence), so
//! minification converges to the average instead of aliasing or darkening, and no octave
//! above the limit is even evaluated. `width = 0` (or NaN) is the unfiltered sum.

use glam::DVec3;

/// Largest `|perlin(p)|` (the maximum of improved noise with Perlin's gradient set).
pub const NOISE_BOUND: f64 = 1.036_353_9;

/// The mean of `|perlin(p)|` over space, what a faded turbulence octave contributes
/// (measured over 10^6 points; see the test `mean_abs_noise_constant`).
pub const MEAN_ABS_NOISE: f64 = 0.22;

/// Frequency ratio between successive octaves.
pub const LACUNARITY: f64 = 2.0;

/// Amplitude ratio between successive octaves.
pub const GAIN: f64 = 0.5;

/// Most octaves a fractal sum evaluates (beyond 16 doublings the features are 1/65536 of
/// the base and below f32 precision of typical coordinates).
pub const MAX_OCTAVES: u32 = 16;

/// `frequency * width` up to which an octave is kept at full amplitude: its lattice spacing
/// is at least two filter widths.
pub const FADE_START: f64 = 0.5;

/// `frequency * width` from which an octave is dropped: its lattice spacing is below one
/// filter width.
pub const FADE_END: f64 = 1.0;

/// Ken Perlin's permutation of 0..=255 (the reference table of improved noise).
const PERM: [u8; 256] = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69,
    142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219,
    203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175,
    74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60, 211, 133, 230,
    220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216, 80, 73, 209, 76,
    132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173,
    186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206,
    59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163,
    70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232,
    178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162,
    241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184, 84, 204,
    176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141,
    128, 195, 78, 66, 215, 61, 156, 180,
];

/// Per-octave offsets (irrational-looking, so octave lattices never line up).
const OCTAVE_SHIFT: DVec3 = DVec3::new(19.137, 7.593, 31.771);

#[inline]
fn perm(i: usize) -> usize {
    usize::from(PERM[i & 255])
}

#[inline]
fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

#[inline]
fn lerp(t: f64, a: f64, b: f64) -> f64 {
    a + t * (b - a)
}

/// Perlin's sixteen gradients (his twelve cube-edge directions, four repeated), indexed by
/// the low four bits of a hash: the table form of his `grad` function, with the same sums.
/// A table instead of his data-dependent branches, which mispredict and cost several times
/// the arithmetic.
const GRADIENTS: [[f64; 3]; 16] = [
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
    [1.0, -1.0, 0.0],
    [-1.0, -1.0, 0.0],
    [1.0, 0.0, 1.0],
    [-1.0, 0.0, 1.0],
    [1.0, 0.0, -1.0],
    [-1.0, 0.0, -1.0],
    [0.0, 1.0, 1.0],
    [0.0, -1.0, 1.0],
    [0.0, 1.0, -1.0],
    [0.0, -1.0, -1.0],
    [1.0, 1.0, 0.0],
    [0.0, -1.0, 1.0],
    [-1.0, 1.0, 0.0],
    [0.0, -1.0, -1.0],
];

/// The dot product of offset `(x, y, z)` with the gradient chosen by `hash`.
#[inline]
fn grad(hash: usize, x: f64, y: f64, z: f64) -> f64 {
    let [gx, gy, gz] = GRADIENTS[hash & 15];
    gx * x + gy * y + gz * z
}

/// `x.floor()` without a library call (baseline x86-64 has no rounding instruction, and
/// `floor` becomes a call to libm): exact for every finite `x`; NaN and infinities pass
/// through as `floor` would return them.
#[inline]
#[must_use]
pub fn fast_floor(x: f64) -> f64 {
    // From 2^52 on every f64 is a whole number.
    if x.abs() < 4_503_599_627_370_496.0 {
        // Truncation, one less for negative fractions; no data-dependent branch (random
        // signs would mispredict it half the time).
        let t = x as i64 as f64;
        t - f64::from(u8::from(t > x))
    } else {
        x
    }
}

/// The lattice cell (wrapped to the 256-periodic table) and the offset within it.
#[inline]
fn cell(x: f64) -> (usize, f64) {
    let f = fast_floor(x);
    // `as i64` saturates for huge values; the wrap keeps the index in the table.
    ((f as i64 & 255) as usize, (x - f).clamp(0.0, 1.0))
}

/// Perlin's improved noise at `p`, in `[-NOISE_BOUND, NOISE_BOUND]`; 0 if `p` is not finite.
#[must_use]
pub fn perlin(p: DVec3) -> f64 {
    if !p.is_finite() {
        return 0.0;
    }
    let ((xi, x), (yi, y), (zi, z)) = (cell(p.x), cell(p.y), cell(p.z));
    let (u, v, w) = (fade(x), fade(y), fade(z));
    let a = perm(xi) + yi;
    let (aa, ab) = (perm(a) + zi, perm(a + 1) + zi);
    let b = perm(xi + 1) + yi;
    let (ba, bb) = (perm(b) + zi, perm(b + 1) + zi);
    lerp(
        w,
        lerp(
            v,
            lerp(u, grad(perm(aa), x, y, z), grad(perm(ba), x - 1.0, y, z)),
            lerp(
                u,
                grad(perm(ab), x, y - 1.0, z),
                grad(perm(bb), x - 1.0, y - 1.0, z),
            ),
        ),
        lerp(
            v,
            lerp(
                u,
                grad(perm(aa + 1), x, y, z - 1.0),
                grad(perm(ba + 1), x - 1.0, y, z - 1.0),
            ),
            lerp(
                u,
                grad(perm(ab + 1), x, y - 1.0, z - 1.0),
                grad(perm(bb + 1), x - 1.0, y - 1.0, z - 1.0),
            ),
        ),
    )
}

/// The weight in `[0, 1]` of an octave of `frequency` for a filter `width` (see the module
/// documentation): 1 below [`FADE_START`], 0 above [`FADE_END`], a smoothstep between.
#[must_use]
pub fn octave_weight(frequency: f64, width: f64) -> f64 {
    let x = frequency * width;
    if x.is_nan() || x <= FADE_START {
        return 1.0;
    }
    let t = ((x - FADE_START) / (FADE_END - FADE_START)).clamp(0.0, 1.0);
    1.0 - t * t * (3.0 - 2.0 * t)
}

/// Sum of the amplitudes of `octaves` octaves (the normaliser of the fractal sums).
fn amplitude_sum(octaves: u32) -> f64 {
    (0..octaves).map(|i| GAIN.powi(i as i32)).sum()
}

/// The shared octave loop: `sum_i amp_i * (w_i * term(noise_i) + (1 - w_i) * mean)`,
/// normalised by the amplitude sum. Stops at the first octave of weight 0.
fn fractal(p: DVec3, octaves: u32, width: f64, mean: f64, term: impl Fn(f64) -> f64) -> f64 {
    if !p.is_finite() {
        return mean;
    }
    let octaves = octaves.clamp(1, MAX_OCTAVES);
    let width = if width.is_nan() { 0.0 } else { width.abs() };
    let (mut sum, mut amp, mut freq) = (0.0, 1.0, 1.0);
    let mut rest = amplitude_sum(octaves);
    let norm = rest;
    for i in 0..octaves {
        let w = octave_weight(freq, width);
        if w <= 0.0 {
            break;
        }
        let n = perlin(p * freq + f64::from(i) * OCTAVE_SHIFT);
        sum += amp * (w * term(n) + (1.0 - w) * mean);
        rest -= amp;
        amp *= GAIN;
        freq *= LACUNARITY;
    }
    (sum + rest.max(0.0) * mean) / norm
}

/// Fractional Brownian motion: band-limited sum of noise octaves, in about `[-1, 1]`
/// (never beyond `±NOISE_BOUND`). `width` is the filter footprint in the units of `p`
/// (0 = unfiltered); octaves above the limit fade to 0.
#[must_use]
pub fn fbm(p: DVec3, octaves: u32, width: f64) -> f64 {
    fractal(p, octaves, width, 0.0, |n| n)
}

/// Turbulence (Perlin 1985): band-limited sum of `|noise|` octaves, in `[0, NOISE_BOUND]`,
/// mostly below 0.6. Faded octaves contribute [`MEAN_ABS_NOISE`], and so does every octave
/// at a non-finite `p`.
#[must_use]
pub fn turbulence(p: DVec3, octaves: u32, width: f64) -> f64 {
    fractal(p, octaves, width, MEAN_ABS_NOISE, f64::abs)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A deterministic pseudo-random point generator (splitmix64) for sampling space.
    pub(crate) fn points(n: usize, scale: f64) -> impl Iterator<Item = DVec3> {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = s;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..n).map(move |_| scale * (DVec3::new(next(), next(), next()) * 2.0 - 1.0))
    }

    #[test]
    #[expect(
        clippy::approx_constant,
        reason = "3.14 is Perlin's reference input, not pi"
    )]
    fn table_is_a_permutation_and_reference_values_match() {
        let mut seen = [false; 256];
        for &v in &PERM {
            assert!(!seen[usize::from(v)], "{v} twice");
            seen[usize::from(v)] = true;
        }
        // Values of Perlin's Java reference implementation.
        let cases = [
            (DVec3::new(3.14, 42.0, 7.0), 0.136_919_958_784_000_12),
            (DVec3::new(-4.2, 10.0, 6.0), 0.142_080_000_000_000_43),
        ];
        for (p, want) in cases {
            let got = perlin(p);
            assert!((got - want).abs() < 1e-12, "noise{p} = {got}, want {want}");
        }
    }

    #[test]
    fn deterministic_zero_on_lattice_and_bounded() {
        for p in points(20_000, 300.0) {
            let n = perlin(p);
            assert_eq!(n.to_bits(), perlin(p).to_bits());
            assert!(n.abs() <= NOISE_BOUND, "{p}: {n}");
            assert_eq!(perlin(p.floor()), 0.0);
            let f = fbm(p, 6, 0.0);
            assert!(f.abs() <= NOISE_BOUND, "fbm {p}: {f}");
            let t = turbulence(p, 6, 0.0);
            assert!((0.0..=NOISE_BOUND).contains(&t), "turbulence {p}: {t}");
        }
    }

    /// No jump across lattice cell faces: the noise is Lipschitz with a small constant, and
    /// points just either side of a face agree to first order.
    #[test]
    fn continuous_across_lattice_cells() {
        // |grad noise| of improved noise is below 4 (each gradient has length sqrt 2, the
        // fade's slope is at most 15/8).
        const LIPSCHITZ: f64 = 4.0;
        let eps = 1e-7;
        for p in points(5_000, 50.0) {
            for k in 0..3 {
                let (mut face, mut axis) = (p, DVec3::ZERO);
                face[k] = p[k].round();
                axis[k] = 1.0;
                let (a, b) = (perlin(face - eps * axis), perlin(face + eps * axis));
                assert!((a - b).abs() <= LIPSCHITZ * 2.0 * eps, "{face}: {a} vs {b}");
            }
            let d = 1e-3 * DVec3::new(0.6, -0.48, 0.64);
            let step = (perlin(p + d) - perlin(p)).abs();
            assert!(step <= LIPSCHITZ * d.length(), "{p}: step {step}");
        }
    }

    /// The table against Perlin's branching `grad`, for every hash.
    #[test]
    fn gradient_table_is_perlins_grad() {
        fn reference(h: usize, x: f64, y: f64, z: f64) -> f64 {
            let u = if h < 8 { x } else { y };
            let v = if h < 4 {
                y
            } else if h == 12 || h == 14 {
                x
            } else {
                z
            };
            (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
        }
        for p in points(100, 1.0) {
            for h in 0..16 {
                assert_eq!(
                    grad(h, p.x, p.y, p.z),
                    reference(h, p.x, p.y, p.z),
                    "hash {h}"
                );
            }
        }
    }

    #[test]
    fn fast_floor_is_floor() {
        let two52 = 2.0f64.powi(52);
        let specials = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            two52 - 0.5,
            0.5 - two52,
            two52,
            -two52,
        ];
        let extremes = [f64::MAX, f64::MIN, f64::INFINITY, f64::NEG_INFINITY];
        let random = points(10_000, 1e6).map(|p| p.x);
        for x in specials.into_iter().chain(extremes).chain(random) {
            assert_eq!(fast_floor(x), x.floor(), "{x}");
        }
        assert!(fast_floor(f64::NAN).is_nan());
    }

    #[test]
    fn mean_abs_noise_constant() {
        let n = 1_000_000;
        let mean: f64 = points(n, 200.0).map(|p| perlin(p).abs()).sum::<f64>() / n as f64;
        assert!((mean - MEAN_ABS_NOISE).abs() < 0.01, "measured {mean}");
    }

    #[test]
    fn non_finite_inputs_give_the_mean() {
        for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let p = DVec3::new(0.5, v, 0.25);
            assert_eq!(perlin(p), 0.0);
            assert_eq!(fbm(p, 5, 0.0), 0.0);
            assert!((turbulence(p, 5, 0.0) - MEAN_ABS_NOISE).abs() < 1e-12);
            assert!(fbm(DVec3::splat(0.3), 5, v).is_finite());
        }
        for big in [1e15, -1e300, f64::MAX] {
            assert!(fbm(DVec3::new(big, 1.5, -big), 8, 0.0).is_finite());
        }
    }

    #[test]
    fn octaves_fade_above_the_nyquist_limit() {
        assert_eq!(octave_weight(1.0, 0.0), 1.0);
        assert_eq!(octave_weight(1.0, FADE_START), 1.0);
        assert_eq!(octave_weight(1.0, FADE_END), 0.0);
        let mid = octave_weight(1.0, 0.5 * (FADE_START + FADE_END));
        assert!((mid - 0.5).abs() < 1e-12);
        // A footprint wider than the base lattice: the sums are their means.
        for p in points(100, 10.0) {
            assert_eq!(fbm(p, 6, 2.0), 0.0);
            assert!((turbulence(p, 6, 2.0) - MEAN_ABS_NOISE).abs() < 1e-12);
            // A tiny footprint changes nothing.
            assert_eq!(fbm(p, 6, 1e-9), fbm(p, 6, 0.0));
        }
        // Variance drops as the footprint grows (fewer octaves survive).
        let var = |w: f64| {
            let n = 20_000;
            points(n, 40.0).map(|p| fbm(p, 8, w).powi(2)).sum::<f64>() / n as f64
        };
        let (v0, v1, v2) = (var(0.0), var(0.1), var(0.6));
        assert!(v0 > v1 && v1 > v2 && v2 > 0.0, "{v0} {v1} {v2}");
    }
}
