//! Importance sampling of an environment for the path tracer (the textbook's §9.6):
//! directions drawn in proportion to the source image's luminance times the solid angle
//! of each texel (`sin θ` in the equirectangular layout), and the density of any direction
//! under that choice, so that samples of the environment and of the surface's BRDF can be
//! combined by multiple importance sampling. Texels are chosen by their piecewise-constant
//! distribution (rows, then a texel in the row), and a direction uniformly inside the
//! chosen texel's `(u, v)` cell.

use std::f32::consts::PI;

use glam::Vec3;

use super::equirect::{dir_to_uv, uv_dir, Plane};

/// The luminance floor, relative to the mean, so that no direction has zero density (a
/// black texel can still be reached: the estimator stays unbiased where the bilinear
/// lookup blends a bright neighbour in).
const FLOOR: f32 = 1e-3;

/// Cumulative distributions over an environment's texels.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvSampler {
    width: usize,
    height: usize,
    /// Per row, the cumulative share of that row's texels (`width + 1` values, 0 to 1).
    rows: Vec<f32>,
    /// Cumulative share of the rows (`height + 1` values, 0 to 1).
    marginal: Vec<f32>,
    /// Each texel's probability (its weight over the total).
    prob: Vec<f32>,
}

fn cdf(weights: &[f32]) -> (Vec<f32>, f32) {
    let mut out = Vec::with_capacity(weights.len() + 1);
    let mut sum = 0.0f64;
    out.push(0.0);
    for &w in weights {
        sum += f64::from(w);
        out.push(sum as f32);
    }
    let total = sum as f32;
    if total > 0.0 {
        for v in &mut out {
            *v /= total;
        }
    }
    if let Some(last) = out.last_mut() {
        *last = 1.0;
    }
    (out, total)
}

/// The index `i` with `cdf[i] <= x < cdf[i + 1]`.
fn find(cdf: &[f32], x: f32) -> usize {
    let n = cdf.len() - 1;
    cdf.partition_point(|&c| c <= x)
        .saturating_sub(1)
        .min(n - 1)
}

impl EnvSampler {
    /// The distributions over `plane`'s texels.
    #[must_use]
    pub(super) fn new(plane: &Plane) -> Self {
        let (w, h) = (plane.width.max(1), plane.height.max(1));
        let lum = |c: Vec3| {
            let l = 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
            if l.is_finite() {
                l.max(0.0)
            } else {
                0.0
            }
        };
        let mut weights = vec![0.0f32; w * h];
        let mut mean = 0.0f64;
        for y in 0..plane.height {
            let sin = libm::sinf((y as f32 + 0.5) / h as f32 * PI);
            for x in 0..plane.width {
                let l = lum(plane.texel(x, y));
                mean += f64::from(l);
                weights[y * w + x] = l * sin;
            }
        }
        let floor = (mean / (w * h) as f64) as f32 * FLOOR + 1e-12;
        for y in 0..h {
            let sin = libm::sinf((y as f32 + 0.5) / h as f32 * PI);
            for v in &mut weights[y * w..(y + 1) * w] {
                *v += floor * sin;
            }
        }
        let mut rows = Vec::with_capacity((w + 1) * h);
        let mut row_sums = Vec::with_capacity(h);
        for y in 0..h {
            let (c, total) = cdf(&weights[y * w..(y + 1) * w]);
            rows.extend_from_slice(&c);
            row_sums.push(total);
        }
        let (marginal, total) = cdf(&row_sums);
        let prob = weights.iter().map(|&v| v / total).collect();
        Self {
            width: w,
            height: h,
            rows,
            marginal,
            prob,
        }
    }

    /// A direction (in the image's frame) for two uniform numbers in `[0, 1)`, and its
    /// density per unit solid angle.
    #[must_use]
    pub fn sample(&self, u1: f32, u2: f32) -> (Vec3, f32) {
        let y = find(&self.marginal, u1);
        let row = &self.rows[y * (self.width + 1)..(y + 1) * (self.width + 1)];
        let x = find(row, u2);
        // Where inside the texel: the remainders of the two choices, rescaled.
        let fy = {
            let (a, b) = (self.marginal[y], self.marginal[y + 1]);
            if b > a {
                ((u1 - a) / (b - a)).clamp(0.0, 1.0)
            } else {
                0.5
            }
        };
        let fx = {
            let (a, b) = (row[x], row[x + 1]);
            if b > a {
                ((u2 - a) / (b - a)).clamp(0.0, 1.0)
            } else {
                0.5
            }
        };
        let u = (x as f32 + fx) / self.width as f32;
        let v = (y as f32 + fy) / self.height as f32;
        let d = uv_dir(u, v);
        (d, self.pdf_texel(x, y, v))
    }

    /// The density of direction `d` (in the image's frame) per unit solid angle.
    #[must_use]
    pub fn pdf(&self, d: Vec3) -> f32 {
        let (u, v) = dir_to_uv(d.normalize_or_zero());
        let x = ((u * self.width as f32) as usize).min(self.width - 1);
        let y = ((v * self.height as f32) as usize).min(self.height - 1);
        self.pdf_texel(x, y, v)
    }

    /// A texel's probability spread over its solid angle, `(2π/w)(π/h) sin θ`.
    fn pdf_texel(&self, x: usize, y: usize, v: f32) -> f32 {
        let sin = libm::sinf(v * PI);
        if sin <= 0.0 {
            return 0.0;
        }
        let p = self.prob[y * self.width + x];
        p * (self.width * self.height) as f32 / (2.0 * PI * PI * sin)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plane(w: usize, h: usize, f: impl Fn(Vec3) -> Vec3) -> Plane {
        let mut rgb = Vec::with_capacity(w * h * 3);
        for y in 0..h {
            for x in 0..w {
                let d = uv_dir((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                rgb.extend_from_slice(&f(d).to_array());
            }
        }
        Plane {
            width: w,
            height: h,
            rgb,
        }
    }

    /// The density integrates to 1 over the sphere, agrees with what `sample` reports, and
    /// `E[L / pdf]` is the environment's integral (a bright lobe on a dim sky).
    #[test]
    fn sampling_density_is_normalised_and_unbiased() {
        let sun = Vec3::new(0.3, 0.8, 0.5).normalize();
        let p = plane(128, 64, |d| {
            Vec3::new(0.2, 0.3, 0.5) + Vec3::splat(40.0) * d.dot(sun).max(0.0).powi(64)
        });
        let s = EnvSampler::new(&p);
        // ∫ pdf dω and ∫ L dω on a fine grid of solid angle.
        let (n, m) = (1024, 512);
        let (mut mass, mut integral) = (0.0f64, 0.0f64);
        for j in 0..m {
            let v = (j as f32 + 0.5) / m as f32;
            let dw = (2.0 * PI / n as f32) * (PI / m as f32) * libm::sinf(v * PI);
            for i in 0..n {
                let d = uv_dir((i as f32 + 0.5) / n as f32, v);
                mass += f64::from(s.pdf(d) * dw);
                let (x, y) = (((i * 128) / n).min(127), ((j * 64) / m).min(63));
                integral += f64::from(
                    0.2126 * p.texel(x, y).x + 0.7152 * p.texel(x, y).y + 0.0722 * p.texel(x, y).z,
                ) * f64::from(dw);
            }
        }
        assert!(
            (mass - 1.0).abs() < 2e-3,
            "the density integrates to {mass}"
        );
        let mut rng = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            (rng >> 40) as f32 / (1u64 << 24) as f32
        };
        let k = 200_000;
        let mut est = 0.0f64;
        let mut off = 0;
        for _ in 0..k {
            let (d, pdf) = s.sample(next(), next());
            // (A direction on a texel's edge may round into its neighbour.)
            if (s.pdf(d) - pdf).abs() > 1e-3 * pdf {
                off += 1;
            }
            let (u, v) = dir_to_uv(d);
            let (x, y) = (
                ((u * 128.0) as usize).min(127),
                ((v * 64.0) as usize).min(63),
            );
            let c = p.texel(x, y);
            est += f64::from((0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z) / pdf);
        }
        est /= f64::from(k);
        assert!(
            off < k / 200,
            "{off} of {k} samples' densities disagree with pdf()"
        );
        assert!(
            (est - integral).abs() < 0.01 * integral,
            "E[L/pdf] = {est}, the integral {integral}"
        );
    }
}
