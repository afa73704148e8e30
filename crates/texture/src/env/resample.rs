//! Area (box) resampling of equirect planes to a smaller size, and the mip pyramid that
//! filtered importance sampling reads.
//!
//! An output texel is the solid-angle average of the source over its footprint: separably,
//! across a row partial texels weigh the fraction covered, down a column every (part of a)
//! source row weighs its exact solid angle `cos θ0 - cos θ1`, so any ratio works, odd sizes
//! included, a constant image stays constant up to rounding, and the rows near the poles
//! (tiny solid angles) do not dominate the coarse levels.

use glam::Vec3;
use rayon::prelude::*;

use super::equirect::Plane;

/// For each of `m` output cells over `n >= m` input cells: the first input index and the
/// weights of the inputs from there (summing to 1). With `polar`, the cells are equirect rows
/// and each overlap weighs its solid angle; otherwise its length.
fn area_weights(n: usize, m: usize, polar: bool) -> Vec<(usize, Vec<f32>)> {
    let scale = n as f64 / m as f64;
    // The measure of [0, t] in input cells.
    let measure = |t: f64| {
        if polar {
            1.0 - libm::cos(std::f64::consts::PI * t / n as f64)
        } else {
            t
        }
    };
    (0..m)
        .map(|i| {
            let (a, b) = (i as f64 * scale, (i + 1) as f64 * scale);
            let first = a.floor() as usize;
            let last = (b.ceil() as usize).clamp(first + 1, n);
            let spans: Vec<f64> = (first..last)
                .map(|j| {
                    let (lo, hi) = (a.max(j as f64), b.min((j + 1) as f64));
                    (measure(hi) - measure(lo)).max(0.0)
                })
                .collect();
            let total: f64 = spans.iter().sum();
            let weights = spans
                .iter()
                .map(|s| if total > 0.0 { (s / total) as f32 } else { 0.0 })
                .collect();
            (first, weights)
        })
        .collect()
}

/// `src` box-resampled to `width×height` (each at most the source's and at least 1).
pub(super) fn resample(src: &Plane, width: usize, height: usize) -> Plane {
    let width = width.clamp(1, src.width);
    let height = height.clamp(1, src.height);
    if (width, height) == (src.width, src.height) {
        return src.clone();
    }
    // Rows first: src.height rows of `width` texels.
    let xw = area_weights(src.width, width, false);
    let mut rows = vec![0.0f32; 3 * width * src.height];
    rows.par_chunks_mut(3 * width)
        .enumerate()
        .for_each(|(y, out)| {
            for (x, (first, ws)) in xw.iter().enumerate() {
                let mut acc = Vec3::ZERO;
                for (k, &w) in ws.iter().enumerate() {
                    acc += src.texel(first + k, y) * w;
                }
                out[3 * x..3 * x + 3].copy_from_slice(&acc.to_array());
            }
        });
    let rows = Plane {
        width,
        height: src.height,
        rgb: rows,
    };
    let yw = area_weights(src.height, height, true);
    let mut rgb = vec![0.0f32; 3 * width * height];
    rgb.par_chunks_mut(3 * width)
        .zip(yw.par_iter())
        .for_each(|(out, (first, ws))| {
            for x in 0..width {
                let mut acc = Vec3::ZERO;
                for (k, &w) in ws.iter().enumerate() {
                    acc += rows.texel(x, first + k) * w;
                }
                out[3 * x..3 * x + 3].copy_from_slice(&acc.to_array());
            }
        });
    Plane { width, height, rgb }
}

/// The source and its successive halvings (each side `max(1, side/2)`) down to 1×1: level
/// `l` has texels about `4^l` times the source's solid angle.
pub(super) struct Pyramid<'a> {
    base: &'a Plane,
    smaller: Vec<Plane>,
}

impl<'a> Pyramid<'a> {
    pub fn new(base: &'a Plane) -> Self {
        let mut smaller: Vec<Plane> = Vec::new();
        loop {
            let last = smaller.last().unwrap_or(base);
            if last.width == 1 && last.height == 1 {
                break;
            }
            let next = resample(last, (last.width / 2).max(1), (last.height / 2).max(1));
            smaller.push(next);
        }
        Self { base, smaller }
    }

    /// Number of levels, the source included.
    pub fn levels(&self) -> usize {
        1 + self.smaller.len()
    }

    fn level(&self, l: usize) -> &Plane {
        match l.checked_sub(1) {
            None => self.base,
            Some(i) => self
                .smaller
                .get(i)
                .or(self.smaller.last())
                .unwrap_or(self.base),
        }
    }

    /// The reads of a trilinear sample at (u, v) and level of detail `lod` (clamped to the
    /// pyramid), weighted by `weight`, appended to `out`: bilinear reads of the levels
    /// `⌊lod⌋` (and the next unless lod is whole) along v, whose u can still be shifted
    /// ([`Pyramid::sum_taps`]).
    pub fn push_taps<'s>(
        &'s self,
        (u, v): (f32, f32),
        lod: f32,
        weight: f32,
        out: &mut Vec<RowTap<'s>>,
    ) {
        let max = (self.levels() - 1) as f32;
        let lod = if lod.is_nan() {
            0.0
        } else {
            lod.clamp(0.0, max)
        };
        let l0 = lod.floor();
        let t = lod - l0;
        let l0 = l0 as usize;
        out.push(self.tap(l0, u, v, (1.0 - t) * weight));
        if t > 0.0 {
            out.push(self.tap(l0 + 1, u, v, t * weight));
        }
    }

    fn tap(&self, l: usize, u: f32, v: f32, weight: f32) -> RowTap<'_> {
        let plane = self.level(l);
        let fy = v * plane.height as f32 - 0.5;
        let y0 = fy.floor();
        let ty = fy - y0;
        // Saturating casts: NaN reads row 0.
        let yi = y0 as i64;
        let last = plane.height as i64 - 1;
        RowTap {
            plane,
            u,
            rows: (
                yi.clamp(0, last) as usize,
                yi.saturating_add(1).clamp(0, last) as usize,
            ),
            ty,
            weight,
        }
    }

    /// `Σ weight·bilinear(u + du, v)` over `taps`.
    pub fn sum_taps(taps: &[RowTap<'_>], du: f32) -> Vec3 {
        let mut acc = Vec3::ZERO;
        for tap in taps {
            let p = tap.plane;
            let w = p.width as i64;
            let fx = (tap.u + du) * p.width as f32 - 0.5;
            let x0 = fx.floor();
            let tx = fx - x0;
            let mut x0 = x0 as i64;
            if !(0..w).contains(&x0) {
                x0 = x0.rem_euclid(w);
            }
            let x1 = if x0 + 1 == w { 0 } else { x0 + 1 };
            let (x0, x1) = (x0 as usize, x1 as usize);
            let (y0, y1) = tap.rows;
            let top = p.texel(x0, y0).lerp(p.texel(x1, y0), tx);
            let bottom = p.texel(x0, y1).lerp(p.texel(x1, y1), tx);
            acc += top.lerp(bottom, tap.ty) * tap.weight;
        }
        acc
    }
}

/// One bilinear read of a pyramid level along a fixed v (rows and their weight decided),
/// at a u the caller may still shift.
#[derive(Clone, Copy)]
pub(super) struct RowTap<'p> {
    plane: &'p Plane,
    u: f32,
    rows: (usize, usize),
    ty: f32,
    weight: f32,
}
