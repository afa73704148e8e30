//! Mip chains: levels 1.. of a texture, box-filtered in linear light.
//!
//! Level k + 1 is `max(1, floor(w / 2))` x `max(1, floor(h / 2))` texels and is computed from
//! level k with an exact box filter: each destination texel is the area-weighted mean of the
//! source texels its footprint covers. Along an even axis that is the usual 2-tap mean; along
//! an odd axis n = 2m + 1 (m >= 1) a destination texel covers n / m source texels, so it takes
//! 3 taps with weights `((m - i) / n, m / n, (i + 1) / n)` on source texels 2i, 2i + 1, 2i + 2;
//! an axis already 1 texel wide is copied. Every source texel contributes exactly its area
//! (its weights over the destination sum to m / n), so each level's mean equals the base
//! level's mean. Filtering is separable, channels are averaged independently (straight
//! alpha, like the bilinear filter).
//!
//! Storage: levels >= 1 of an image in [0, 1] (8- and 16-bit sources) hold linear-light RGBA
//! as 16-bit unsigned normalised integers
//! (8 bytes a texel): the chain costs 2/3 of the RGBA8 base's bytes (sum of 4^-k = 1/3 of
//! the texels at twice the bytes) instead of the 1/3 an RGBA8 sRGB chain would. In exchange
//! the levels carry no visible quantisation (a step is 1.5e-5 in linear light, 20 times
//! finer than the smallest 8-bit sRGB step), a level can be computed from the previous one
//! without accumulating rounding (no full-size f32 scratch image and no sRGB re-encoding per
//! texel), and sampling a level is a plain integer-to-float scale, with no decoding table.
//! Levels of a high-dynamic-range (float) image are float, unclamped ([`MipFormat::Float`]).

use glam::Vec4;
use rayon::prelude::*;

/// How the levels below the base are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum MipFormat {
    /// 16-bit unorm (values clamped to [0, 1]).
    Unorm16,
    /// 32-bit float (high dynamic range; non-finite values become 0).
    Float,
}

/// One level of a mip chain below the base (linear light, row-major), each value already
/// what its format stores (a 16-bit level's values are multiples of 1 / 65535).
#[derive(Clone, Debug)]
pub(crate) struct MipLevel {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[f32; 4]>,
}

pub(crate) const U16_MAX: f32 = 65535.0;

impl MipLevel {
    /// Texel (x, y) in linear light.
    #[inline(always)]
    pub fn fetch(&self, x: u32, y: u32) -> Vec4 {
        Vec4::from_array(self.texels[(y * self.width + x) as usize])
    }
}

/// Number of levels of a full chain for a `width` x `height` base, the base included:
/// `floor(log2(max(width, height))) + 1`.
#[must_use]
pub(crate) fn level_count(width: u32, height: u32) -> usize {
    (32 - width.max(height).max(1).leading_zeros()) as usize
}

/// Size of the level below an `n`-texel axis.
#[inline]
pub(crate) fn half(n: u32) -> u32 {
    (n / 2).max(1)
}

/// The source texels (at most 3) and weights of destination texel `i` along an axis of `n`
/// source texels (see the module docs).
#[inline]
fn taps(i: u32, n: u32) -> ([u32; 3], [f32; 3], usize) {
    if n == 1 {
        ([0, 0, 0], [1.0, 0.0, 0.0], 1)
    } else if n.is_multiple_of(2) {
        ([2 * i, 2 * i + 1, 0], [0.5, 0.5, 0.0], 2)
    } else {
        let (m, nf) = (n / 2, n as f32);
        (
            [2 * i, 2 * i + 1, 2 * i + 2],
            [(m - i) as f32 / nf, m as f32 / nf, (i + 1) as f32 / nf],
            3,
        )
    }
}

/// Builds levels 1.. from a `width` x `height` base whose texels (linear light) `row` writes
/// one row at a time, each level stored as `format` stores it (and the next computed from
/// that). With `parallel`, rows of a level are filtered on the rayon pool; the result is
/// identical either way.
pub(crate) fn build(
    width: u32,
    height: u32,
    row: &(dyn Fn(u32, &mut [Vec4]) + Sync),
    parallel: bool,
    format: MipFormat,
) -> Vec<MipLevel> {
    let count = level_count(width, height);
    let mut levels: Vec<MipLevel> = Vec::with_capacity(count.saturating_sub(1));
    for _ in 1..count {
        let next = match levels.last() {
            None => downsample(width, height, row, parallel, format),
            Some(prev) => {
                let src = |y: u32, out: &mut [Vec4]| {
                    for (x, o) in out.iter_mut().enumerate() {
                        *o = prev.fetch(x as u32, y);
                    }
                };
                downsample(prev.width, prev.height, &src, parallel, format)
            }
        };
        levels.push(next);
    }
    levels
}

/// One box-filter step from a `sw` x `sh` source.
fn downsample(
    sw: u32,
    sh: u32,
    row: &(dyn Fn(u32, &mut [Vec4]) + Sync),
    parallel: bool,
    format: MipFormat,
) -> MipLevel {
    let (dw, dh) = (half(sw), half(sh));
    let xtaps: Vec<_> = (0..dw).map(|i| taps(i, sw)).collect();
    let mut texels = vec![[0f32; 4]; dw as usize * dh as usize];
    let store = match format {
        MipFormat::Unorm16 => |v: f32| f32::from(quantise(v)) * (1.0 / U16_MAX),
        MipFormat::Float => |v: f32| if v.is_finite() { v } else { 0.0 },
    };
    let filter_row = |scratch: &mut (Vec<Vec4>, Vec<Vec4>), (j, out): (usize, &mut [[f32; 4]])| {
        let (src, acc) = scratch;
        acc.iter_mut().for_each(|a| *a = Vec4::ZERO);
        let (ys, wys, ny) = taps(j as u32, sh);
        for t in 0..ny {
            row(ys[t], src);
            for (a, &(xs, wxs, nx)) in acc.iter_mut().zip(&xtaps) {
                let mut s = Vec4::ZERO;
                for k in 0..nx {
                    s += src[xs[k] as usize] * wxs[k];
                }
                *a += s * wys[t];
            }
        }
        for (o, a) in out.iter_mut().zip(acc.iter()) {
            *o = a.to_array().map(store);
        }
    };
    let init = || (vec![Vec4::ZERO; sw as usize], vec![Vec4::ZERO; dw as usize]);
    if parallel {
        texels
            .par_chunks_mut(dw as usize)
            .enumerate()
            .for_each_init(init, filter_row);
    } else {
        let mut scratch = init();
        texels
            .chunks_mut(dw as usize)
            .enumerate()
            .for_each(|r| filter_row(&mut scratch, r));
    }
    MipLevel {
        width: dw,
        height: dh,
        texels,
    }
}

/// The levels below the base in one array: level k's texels (row-major) start at
/// `offset[k]` (k >= 1). One array makes a texel of any level below the base the same load
/// and conversion, whatever its level: eight lanes on different levels read with one loop.
#[derive(Clone, Debug)]
pub(crate) struct Chain {
    pub texels: ChainTexels,
    /// First texel of each level below the base (`offset[0]` is unused).
    pub offset: [u32; 32],
    /// Size of each level, the base's at 0.
    pub size: [(u32, u32); 32],
    /// Levels, the base included.
    pub levels: usize,
}

/// Packs a 16-bit RGBA texel (see [`Chain`]).
#[inline]
pub(crate) fn pack(t: [u16; 4]) -> u64 {
    u64::from(t[0]) | u64::from(t[1]) << 16 | u64::from(t[2]) << 32 | u64::from(t[3]) << 48
}

/// A packed texel in linear light: each channel `as f32 * (1 / 65535)` (the lane sampler
/// decodes with the same operations).
#[inline(always)]
pub(crate) fn unpack(t: u64) -> Vec4 {
    Vec4::new(
        f32::from(t as u16),
        f32::from((t >> 16) as u16),
        f32::from((t >> 32) as u16),
        f32::from((t >> 48) as u16),
    ) * (1.0 / U16_MAX)
}

/// The texels of a [`Chain`].
#[derive(Clone, Debug)]
pub(crate) enum ChainTexels {
    /// 16-bit linear RGBA, each texel packed into a `u64` as `r | g << 16 | b << 32 | a << 48`.
    Unorm16(Vec<u64>),
    /// Float linear RGBA.
    Float(Vec<[f32; 4]>),
}

impl Chain {
    /// The levels below a `width` x `height` base whose texels (linear light) `row` writes
    /// one row at a time (see [`build`]), stored as `format`.
    pub fn new(
        width: u32,
        height: u32,
        row: &(dyn Fn(u32, &mut [Vec4]) + Sync),
        parallel: bool,
        format: MipFormat,
    ) -> Chain {
        let mips = build(width, height, row, parallel, format);
        let count = mips.iter().map(|m| m.texels.len()).sum();
        let (mut offset, mut size) = ([0u32; 32], [(1u32, 1u32); 32]);
        size[0] = (width, height);
        let mut at = 0;
        for (k, m) in mips.iter().enumerate() {
            offset[k + 1] = at;
            size[k + 1] = (m.width, m.height);
            at += m.texels.len() as u32;
        }
        let all = mips.iter().flat_map(|m| m.texels.iter());
        let texels = match format {
            MipFormat::Unorm16 => {
                let mut v = Vec::with_capacity(count);
                v.extend(all.map(|t| pack(t.map(quantise))));
                ChainTexels::Unorm16(v)
            }
            MipFormat::Float => ChainTexels::Float(all.copied().collect()),
        };
        Chain {
            texels,
            offset,
            size,
            levels: mips.len() + 1,
        }
    }

    /// Texel (x, y) of level `level` (>= 1) in linear light (panics if it does not exist).
    #[inline]
    pub fn fetch(&self, level: usize, x: u32, y: u32) -> Vec4 {
        let (w, h) = self.size[level];
        assert!(level >= 1 && level < self.levels && x < w && y < h);
        let i = self.offset[level] as usize + (y * w + x) as usize;
        match &self.texels {
            ChainTexels::Unorm16(t) => unpack(t[i]),
            ChainTexels::Float(t) => Vec4::from_array(t[i]),
        }
    }
}

/// Linear value in [0, 1] -> 16-bit unorm, rounded to nearest (NaN -> 0).
#[inline]
fn quantise(v: f32) -> u16 {
    (v.clamp(0.0, 1.0) * U16_MAX + 0.5) as u16
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_counts_and_sizes() {
        assert_eq!(level_count(1, 1), 1);
        assert_eq!(level_count(2, 1), 2);
        assert_eq!(level_count(37, 20), 6); // 37 18 9 4 2 1
        assert_eq!(level_count(256, 256), 9);
        assert_eq!(level_count(1, 300), 9);
        assert_eq!((half(37), half(1), half(3)), (18, 1, 1));
    }

    #[test]
    fn odd_axis_weights_cover_every_source_texel_once() {
        for n in [1u32, 2, 3, 5, 7, 37, 100, 101] {
            let m = half(n);
            let mut per_source = vec![0f64; n as usize];
            for i in 0..m {
                let (xs, ws, k) = taps(i, n);
                let total: f32 = ws[..k].iter().sum();
                assert!((total - 1.0).abs() < 1e-6, "n {n} i {i}: {total}");
                for t in 0..k {
                    per_source[xs[t] as usize] += f64::from(ws[t]);
                }
            }
            // Each source texel's area, in destination texels: m / n.
            for (j, w) in per_source.iter().enumerate() {
                let want = f64::from(m) / f64::from(n);
                assert!((w - want).abs() < 1e-6, "n {n} texel {j}: {w} vs {want}");
            }
        }
    }
}
