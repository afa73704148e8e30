//! The 2D patterns (chequerboard, UV test grid) and their exact box filter.
//!
//! Both patterns are piecewise constant on axis-aligned rectangles that repeat per cell, and
//! every region is a product `U(u) * V(v)` of a set of columns and a set of rows. The box
//! filter over a footprint `[u0, u1] x [v0, v1]` is therefore a product of two 1D integrals,
//! and a 1D integral of a periodic interval indicator has a closed form (its antiderivative
//! is `floor(x / period) * len + clamp(x mod period - lo, 0, len)`). So the filtered value is
//! exact for any footprint, from a point (the unfiltered pattern) to many periods (the
//! pattern's mean): the chequer as in Apodaca and Gritz and Quilez's filtered checker, the
//! grid by the same argument applied per column and per row.
//!
//! All arithmetic is in f64, after moving the footprint into the first period, so UVs of
//! 10^6 keep their fraction and tiny footprints do not cancel.

use glam::{DVec3, Vec3};

use crate::noise::fast_floor;

/// Footprints narrower than this (in cells) are point samples.
pub const POINT_WIDTH: f64 = 1e-9;

/// Footprints wider than this many periods are the pattern's mean (the remainder of a
/// partial period changes the integral by less than `1 / WHOLE_PERIODS`).
pub const WHOLE_PERIODS: f64 = 1e7;

/// Most columns (and rows) of the UV test grid.
pub const MAX_GRID_CELLS: u32 = 16;

/// Half width of a grid line, as a fraction of a cell (lines are centred on cell edges).
const LINE: f64 = 1.0 / 32.0;

/// The per-cell intervals of the grid's regions along u, then v: the cell interior inside
/// the lines, then the three bars of the letter F (stem, top bar, middle bar; disjoint).
/// v runs downwards, so the top bar has the smaller v. F has no mirror or rotation symmetry:
/// any flip or turn of the texture shows.
const REGIONS_U: [(f64, f64); 4] = [(LINE, 1.0 - LINE), (0.30, 0.42), (0.42, 0.70), (0.42, 0.62)];
const REGIONS_V: [(f64, f64); 4] = [(LINE, 1.0 - LINE), (0.22, 0.78), (0.22, 0.34), (0.46, 0.56)];

/// `x mod period`, in `[0, period]` (`period` itself only by rounding).
fn wrap(x: f64, period: f64) -> f64 {
    (x - fast_floor(x / period) * period).clamp(0.0, period)
}

/// A footprint `[x0, x1]` in cell units, moved into the first period (same length).
fn into_first_period(x0: f64, x1: f64, period: f64) -> (f64, f64) {
    let a = wrap(x0, period);
    (a, a + (x1 - x0))
}

/// The fraction of `[x0, x1]` where `x mod period` lies in `[lo, hi)`
/// (`0 <= lo <= hi <= period`). Exact box filter of a periodic interval indicator.
#[must_use]
pub fn coverage(x0: f64, x1: f64, period: f64, lo: f64, hi: f64) -> f64 {
    let mean = (hi - lo) / period;
    let w = x1 - x0;
    if !(x0.is_finite() && x1.is_finite() && w.is_finite()) || w >= WHOLE_PERIODS * period {
        return mean;
    }
    if w <= POINT_WIDTH {
        let r = wrap(0.5 * (x0 + x1), period);
        return f64::from(u8::from((lo <= r) & (r < hi)));
    }
    let (a, b) = into_first_period(x0, x1, period);
    let antiderivative = |x: f64| {
        let k = fast_floor(x / period);
        k * (hi - lo) + (x - k * period - lo).clamp(0.0, hi - lo)
    };
    ((antiderivative(b) - antiderivative(a)) / w).clamp(0.0, 1.0)
}

/// The fraction of the chequer footprint (in squares) covered by odd squares, where
/// square `(i, j)` is odd if `i + j` is odd (square (0, 0), top left, is even).
#[must_use]
pub fn checker_odd(x: (f64, f64), y: (f64, f64)) -> f64 {
    let fx = coverage(x.0, x.1, 2.0, 1.0, 2.0);
    let fy = coverage(y.0, y.1, 2.0, 1.0, 2.0);
    fx * (1.0 - fy) + fy * (1.0 - fx)
}

/// The UV test grid with its colours in linear light.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    cells: usize,
    /// Colour of column `i` (a hue wheel, left to right).
    columns: [DVec3; MAX_GRID_CELLS as usize],
    /// Brightness of row `j` (light at the top, darker downwards).
    rows: [f64; MAX_GRID_CELLS as usize],
    line: DVec3,
    glyph: DVec3,
}

/// `weights[k][i]`: the fraction of a 1D footprint in region `k` of column (or row) `i`.
type Weights = [[f64; MAX_GRID_CELLS as usize]; 4];

impl Grid {
    /// A grid of `cells` x `cells` per unit UV (clamped to `1..=MAX_GRID_CELLS`), colours
    /// designed in sRGB: hue `i / cells` at saturation 0.6 per column, value 0.9 falling to
    /// 0.45 per row, near-black lines, a white F.
    #[must_use]
    pub fn new(cells: u32) -> Grid {
        let n = cells.clamp(1, MAX_GRID_CELLS) as usize;
        let lin = |c: [f64; 3]| DVec3::from_array(c.map(|v| f64::from(super::linear(v as f32))));
        let mut columns = [DVec3::ZERO; MAX_GRID_CELLS as usize];
        let mut rows = [0.0; MAX_GRID_CELLS as usize];
        for i in 0..n {
            let t = i as f64 / n as f64;
            columns[i] = lin(crate::color::hsv_to_rgb([t, 0.6, 1.0]));
            let down = if n > 1 {
                i as f64 / (n - 1) as f64
            } else {
                0.0
            };
            rows[i] = lin([0.9 - 0.45 * down; 3]).x;
        }
        Grid {
            cells: n,
            columns,
            rows,
            line: lin([0.08; 3]),
            glyph: lin([1.0; 3]),
        }
    }

    /// Number of columns (= rows).
    #[must_use]
    pub fn cells(&self) -> u32 {
        self.cells as u32
    }

    /// Fractions of the footprint `[x0, x1]` (in cells) per region and column.
    fn weights(&self, x0: f64, x1: f64, regions: &[(f64, f64); 4]) -> Weights {
        let n = self.cells;
        let period = n as f64;
        let mut out = [[0.0; MAX_GRID_CELLS as usize]; 4];
        let w = x1 - x0;
        if x0.is_finite() && w.is_finite() && w <= POINT_WIDTH {
            let a = wrap(0.5 * (x0 + x1), period);
            let cell = fast_floor(a).min(period - 1.0);
            for (k, &(lo, hi)) in regions.iter().enumerate() {
                let r = a - cell;
                out[k][cell as usize] = f64::from(u8::from((lo <= r) & (r < hi)));
            }
            return out;
        }
        let narrow = x0.is_finite() && w.is_finite() && w < period;
        if !narrow {
            // Wide footprints: the periodic coverage of every region.
            for (k, &(lo, hi)) in regions.iter().enumerate() {
                for (i, slot) in out[k].iter_mut().take(n).enumerate() {
                    *slot = coverage(x0, x1, period, i as f64 + lo, i as f64 + hi);
                }
            }
            return out;
        }
        // At most two periods' worth of cells: intersect the footprint with each.
        let (a, b) = into_first_period(x0, x1, period);
        let mut cell = fast_floor(a);
        while cell < b {
            let i = (cell as usize) % n;
            for (k, &(lo, hi)) in regions.iter().enumerate() {
                let overlap = b.min(cell + hi) - a.max(cell + lo);
                out[k][i] += overlap.max(0.0) / w;
            }
            cell += 1.0;
        }
        out
    }

    /// The box-filtered colour (linear RGB) and height (1 in cell interiors, 0 on lines
    /// and the letter) over the footprint `[x.0, x.1] x [y.0, y.1]`, in cells.
    #[must_use]
    pub fn filtered(&self, x: (f64, f64), y: (f64, f64)) -> (Vec3, f64) {
        let wu = self.weights(x.0, x.1, &REGIONS_U);
        let wv = self.weights(y.0, y.1, &REGIONS_V);
        let n = self.cells;
        let (mut colour, mut inner, mut glyph) = (DVec3::ZERO, 0.0, 0.0);
        for k in 0..4 {
            let su: DVec3 = (0..n).map(|i| self.columns[i] * wu[k][i]).sum();
            let sv: f64 = (0..n).map(|j| self.rows[j] * wv[k][j]).sum();
            let cover = wu[k][..n].iter().sum::<f64>() * wv[k][..n].iter().sum::<f64>();
            // Region 0 is the whole interior; the letter's bars are cut out of it.
            if k == 0 {
                (colour, inner) = (su * sv, cover);
            } else {
                (colour, glyph) = (colour - su * sv, glyph + cover);
            }
        }
        let line = (1.0 - inner).max(0.0);
        let rgb = colour.max(DVec3::ZERO) + self.line * line + self.glyph * glyph;
        (rgb.as_vec3(), (inner - glyph).clamp(0.0, 1.0))
    }
}
