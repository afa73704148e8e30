//! The diagram's raster layers: the horseshoe's fill and an image's chromaticities.

use rayon::prelude::*;

use super::draw::Frame;
use super::fill::{fill, smooth_fill_linear, FillStyle};
use super::gamut::locus_polygon;
use super::pixels::PixelStyle;
use super::ChromaOptions;
use crate::color::RgbSpace;
use crate::RgbaImage;

/// Spacing in pixels of the grid on which the smooth fill is evaluated.
const COARSE: u32 = 2;

/// Entries of the linear -> 8-bit sRGB table of the fill (one code value at worst, as
/// the framebuffer's table).
const ENCODE_LUT: usize = 1 << 14;

/// The raster of the horseshoe's fill over the whole plot square (clipped by the caller).
pub(super) fn fill_image(opts: &ChromaOptions, f: &Frame) -> RgbaImage {
    let n = f.side as u32;
    let space = RgbSpace::srgb();
    let locus = locus_polygon(opts.observer, opts.plane);
    let [mut lo, mut hi] = [[f64::INFINITY; 2], [f64::NEG_INFINITY; 2]];
    for p in &locus {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let lut: Vec<u8> = (0..ENCODE_LUT)
        .map(|i| {
            (crate::texture::linear_to_srgb(i as f32 / (ENCODE_LUT - 1) as f32) * 255.0).round()
                as u8
        })
        .collect();
    let lut = &lut;
    let margin = 2.0 * (f.bounds[1] - f.bounds[0]) / f64::from(f.side);
    let outside = |p: [f64; 2]| {
        p[0] < lo[0] - margin
            || p[0] > hi[0] + margin
            || p[1] < lo[1] - margin
            || p[1] > hi[1] + margin
    };
    // The smooth fill is evaluated every COARSE pixels and interpolated bilinearly in
    // linear light (it is smooth by construction, so the interpolation error is far below
    // one 8-bit step); chromaticities with y <= 0 are nudged to y = 1e-9 so the field stays
    // continuous up to the purple line.
    let coarse = COARSE;
    let m = if opts.fill == FillStyle::Smooth {
        n / coarse + 2
    } else {
        0
    };
    let nodes: Vec<[f64; 3]> = (0..m)
        .into_par_iter()
        .flat_map_iter(|b| {
            let space = &space;
            (0..m).map(move |a| {
                let p = f.unpx(a * coarse, b * coarse);
                let xy = opts.plane.to_xy(p);
                smooth_fill_linear(space, [xy[0], xy[1].max(1e-9)])
            })
        })
        .collect();
    let nodes = &nodes;
    let pixels: Vec<[u8; 4]> = (0..n)
        .into_par_iter()
        .flat_map_iter(|j| {
            let space = &space;
            (0..n).map(move |i| {
                let p = f.unpx(i, j);
                // Outside the locus's bounding box (plus a pixel for anti-aliasing) nothing
                // shows through the clip: skip the work.
                if outside(p) {
                    return [0, 0, 0, 0];
                }
                if opts.fill == FillStyle::Smooth {
                    let (a, b) = ((i / coarse) as usize, (j / coarse) as usize);
                    let (fx, fy) = (
                        f64::from(i % coarse) / f64::from(coarse),
                        f64::from(j % coarse) / f64::from(coarse),
                    );
                    let at = |a: usize, b: usize| nodes[b * m as usize + a];
                    let (c00, c10, c01, c11) =
                        (at(a, b), at(a + 1, b), at(a, b + 1), at(a + 1, b + 1));
                    let e = |k: usize| {
                        let v = (c00[k] * (1.0 - fx) + c10[k] * fx) * (1.0 - fy)
                            + (c01[k] * (1.0 - fx) + c11[k] * fx) * fy;
                        lut[(v.clamp(0.0, 1.0) * (ENCODE_LUT - 1) as f64).round() as usize]
                    };
                    return [e(0), e(1), e(2), 255];
                }
                let rgb = fill(opts.fill, space, opts.plane.to_xy(p));
                let q = |v: f64| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
                [q(rgb[0]), q(rgb[1]), q(rgb[2]), 255]
            })
        })
        .collect();
    RgbaImage {
        width: n,
        height: n,
        pixels,
    }
}

/// The image's chromaticities as a raster over the plot square.
pub(super) fn pixel_image(px: &super::PixelReport, style: PixelStyle, f: &Frame) -> RgbaImage {
    let n = f.side as usize;
    let mut counts = vec![0u64; n * n];
    let mut sums = vec![[0f32; 3]; n * n];
    for (xy, count, mean) in px.occupied() {
        let (x, y) = f.px_xy(xy);
        let (i, j) = ((x - f.left).floor(), (y - f.top).floor());
        if i < 0.0 || j < 0.0 || i >= n as f32 || j >= n as f32 {
            continue;
        }
        let k = j as usize * n + i as usize;
        counts[k] += u64::from(count);
        for (s, m) in sums[k].iter_mut().zip(mean) {
            *s += m * count as f32;
        }
    }
    let mut pixels = vec![[0u8; 4]; n * n];
    let max = counts.iter().copied().max().unwrap_or(0).max(1) as f32;
    let r = (2.0 * f.s).round().max(1.0) as isize;
    let q = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    for pass in 0..2 {
        for (k, &count) in counts.iter().enumerate() {
            if count == 0 {
                continue;
            }
            let colour = match style {
                PixelStyle::Density => {
                    let t = libm::logf(1.0 + count as f32) / libm::logf(1.0 + max);
                    let [r, g, b] = inferno(t);
                    [r, g, b, 255]
                }
                PixelStyle::Scatter if pass == 0 => [0x20, 0x20, 0x20, 255],
                PixelStyle::Scatter => {
                    let s = sums[k];
                    let c = count as f32;
                    [q(s[0] / c), q(s[1] / c), q(s[2] / c), 255]
                }
            };
            // Scatter: a dark disc of radius r + 1 first, the colour of radius r on top.
            let rad = if style == PixelStyle::Scatter && pass == 0 {
                r + 1
            } else {
                r
            };
            if style == PixelStyle::Density && pass == 0 {
                continue;
            }
            let (i, j) = ((k % n) as isize, (k / n) as isize);
            for dj in -rad..=rad {
                for di in -rad..=rad {
                    let (x, y) = (i + di, j + dj);
                    if di * di + dj * dj <= rad * rad
                        && x >= 0
                        && y >= 0
                        && (x as usize) < n
                        && (y as usize) < n
                    {
                        pixels[y as usize * n + x as usize] = colour;
                    }
                }
            }
        }
    }
    RgbaImage {
        width: n as u32,
        height: n as u32,
        pixels,
    }
}

/// A compact approximation of matplotlib's "inferno" colour map, t in [0, 1].
fn inferno(t: f32) -> [u8; 3] {
    const STOPS: [[f32; 3]; 6] = [
        [0.0, 0.0, 0.016],
        [0.258, 0.039, 0.408],
        [0.576, 0.149, 0.404],
        [0.867, 0.319, 0.227],
        [0.988, 0.647, 0.039],
        [0.988, 1.0, 0.643],
    ];
    let x = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f32;
    let i = (x as usize).min(STOPS.len() - 2);
    let f = x - i as f32;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    [0, 1, 2].map(|k| ((a[k] + (b[k] - a[k]) * f) * 255.0).round() as u8)
}
