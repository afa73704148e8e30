//! Solid (3D) textures evaluated at an object-space point: wood, marble, fBm noise. Each
//! returns a scalar in `[0, 1]` that the caller mixes between two colours in linear light,
//! so filtering the scalar filters the colour exactly.
//!
//! The rings and veins have the profile `((1 - cos 2 pi t) / 2)^2` of their phase `t`: 0 at
//! whole `t`, a peak of 1 at `t = 1/2` narrower than the trough, mean [`PROFILE_MEAN`].
//! Written as a Fourier series, `3/8 - cos(2 pi t) / 2 + cos(4 pi t) / 8`, it filters
//! exactly: under a Gaussian filter `W` periods wide (with the variance of a box that wide,
//! `sigma = W / sqrt 12`) harmonic `k` is multiplied by `exp(-pi^2 k^2 W^2 / 6)`, so rings
//! and veins fade to their mean as they shrink below a pixel instead of aliasing into moiré.
//! The noise that perturbs them is band-limited by frequency clamping (`noise.rs`). A
//! non-finite point has no defined pattern and gives the mean.

use std::f64::consts::{PI, TAU};

use glam::DVec3;

use super::super::noise::{fast_floor, fbm, turbulence};

/// Octaves of the noise that wobbles the wood rings.
const WOOD_OCTAVES: u32 = 4;
/// Frequency of the wood noise per axis: stretched along the trunk (Y), as grain is.
const WOOD_NOISE: DVec3 = DVec3::new(3.0, 0.75, 3.0);
/// Octaves of the marble turbulence.
const MARBLE_OCTAVES: u32 = 6;
/// Frequency of the marble turbulence.
const MARBLE_NOISE: f64 = 4.0;

/// The mean of the ring and vein profile.
pub const PROFILE_MEAN: f64 = 0.375;

/// The factor by which a unit-frequency cosine shrinks under a footprint `periods` wide.
#[must_use]
pub fn cosine_attenuation(periods: f64) -> f64 {
    if periods.is_nan() {
        return 1.0;
    }
    libm::exp(-PI * PI * periods * periods / 6.0)
}

/// `((1 - cos 2 pi t) / 2)^2`, filtered over `periods` periods (see the module docs).
#[must_use]
pub fn profile(t: f64, periods: f64) -> f64 {
    let t = t - fast_floor(t);
    let first = 0.5 * libm::cos(TAU * t) * cosine_attenuation(periods);
    let second = 0.125 * libm::cos(2.0 * TAU * t) * cosine_attenuation(2.0 * periods);
    (PROFILE_MEAN - first + second).clamp(0.0, 1.0)
}

/// Wood: concentric rings around the Y axis, `rings` per unit of radius, each ring's radius
/// displaced by up to about `wobble` ring widths of fBm. 0 = light wood (at radii that are
/// whole multiples of `1 / rings` when undisplaced), 1 = the middle of a dark ring.
#[must_use]
pub fn wood(p: DVec3, width: f64, rings: f64, wobble: f64) -> f64 {
    if !p.is_finite() {
        return PROFILE_MEAN;
    }
    let n = WOOD_NOISE.max_element();
    let noise = if wobble == 0.0 {
        0.0
    } else {
        wobble * fbm(p * WOOD_NOISE, WOOD_OCTAVES, width * n)
    };
    profile(libm::hypot(p.x, p.z) * rings + noise, width * rings)
}

/// Marble (after Perlin 1985): the profile of the phase `frequency (x + amount *
/// turb(p))`; 1 = the middle of a vein.
#[must_use]
pub fn marble(p: DVec3, width: f64, frequency: f64, amount: f64) -> f64 {
    if !p.is_finite() {
        return PROFILE_MEAN;
    }
    let turb = if amount == 0.0 {
        0.0
    } else {
        turbulence(p * MARBLE_NOISE, MARBLE_OCTAVES, width * MARBLE_NOISE)
    };
    profile((p.x + amount * turb) * frequency, width * frequency)
}

/// fBm height: `0.5 + 0.5 fbm(frequency p)`, clamped to `[0, 1]`.
#[must_use]
pub fn noise_height(p: DVec3, width: f64, frequency: f64, octaves: u32) -> f64 {
    if !p.is_finite() {
        return 0.5;
    }
    (0.5 + 0.5 * fbm(p * frequency, octaves, width * frequency)).clamp(0.0, 1.0)
}
