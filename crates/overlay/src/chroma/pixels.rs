//! The chromaticities of an image's pixels: a fine xy histogram (for a scatter or density
//! plot on any plane) and the fraction of pixels outside each gamut.
//!
//! Pixels are encoded sRGB (the texture loader's output). Pixels darker than
//! [`DARK_Y`] have no meaningful chromaticity (8-bit quantisation moves it by more than
//! 0.05) and are counted apart, not plotted.

use rayon::prelude::*;

use crate::color::{srgb_decode, RgbSpace};
use crate::texture::Texture;

/// Relative luminance below which a pixel's chromaticity is not plotted.
pub const DARK_Y: f64 = 1e-3;
/// Histogram bins per unit of x and of y (over [0, 1] x [0, 1]).
pub const BINS: usize = 1024;
/// Distance (in xy) within which a chromaticity on a gamut's edge counts as inside: the
/// rounded IEC matrix puts pure sRGB red 7e-5 outside its own triangle.
pub const EDGE_TOLERANCE: f64 = 2e-4;

/// How an image's chromaticities are drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PixelStyle {
    /// Dots in the mean colour of the pixels that fall there.
    #[default]
    Scatter,
    /// A heat map of the (log) number of pixels.
    Density,
}

/// An image's chromaticities.
#[derive(Clone, Debug)]
pub struct PixelReport {
    /// Image name (for the legend and the report).
    pub name: String,
    /// Number of pixels in the image.
    pub total: u64,
    /// Pixels darker than [`DARK_Y`] (not in the histogram).
    pub dark: u64,
    /// Pixel count per xy bin, row-major: `bins[j * BINS + i]` for x in [i, i+1) / BINS.
    pub counts: Vec<u32>,
    /// Sum of the pixels' encoded sRGB per bin (for the mean colour).
    pub colour_sums: Vec<[f32; 3]>,
    /// For each gamut analysed: its name and the fraction of non-dark pixels outside it.
    pub outside: Vec<(String, f64)>,
}

/// Whether `xy` is inside `space`'s triangle, allowing [`EDGE_TOLERANCE`].
#[must_use]
pub fn inside_gamut(space: &RgbSpace, xy: [f64; 2]) -> bool {
    let [a, b, c] = space.primaries;
    let orient = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    let sign = orient.signum();
    [(a, b), (b, c), (c, a)].iter().all(|&(p, q)| {
        let len = libm::hypot(q[0] - p[0], q[1] - p[1]);
        let side = ((q[0] - p[0]) * (xy[1] - p[1]) - (q[1] - p[1]) * (xy[0] - p[0])) * sign;
        side / len >= -EDGE_TOLERANCE
    })
}

/// Analyses `image` (encoded sRGB): histogram, dark pixels, fractions outside `gamuts`.
#[must_use]
pub fn analyse(image: &Texture, gamuts: &[RgbSpace]) -> PixelReport {
    let srgb = RgbSpace::srgb();
    let lut: Vec<f64> = (0..256)
        .map(|v| srgb_decode(f64::from(v) / 255.0))
        .collect();
    // One partial histogram (16 MiB) per thread, not per rayon job.
    let width = image.width.max(1) as usize;
    let texels = image.to_srgb8();
    let rows = texels.len().div_ceil(width);
    let bands = rayon::current_num_threads().clamp(1, rows.max(1));
    let band_rows = rows.div_ceil(bands).max(1);
    let part = texels
        .par_chunks(band_rows * width)
        .map(|band| {
            let mut acc = Partial {
                counts: vec![0; BINS * BINS],
                sums: vec![[0.0; 3]; BINS * BINS],
                dark: 0,
                outside: vec![0; gamuts.len()],
            };
            for t in band {
                let lin = [lut[t[0] as usize], lut[t[1] as usize], lut[t[2] as usize]];
                let xyz = srgb.linear_to_xyz(lin);
                let s = xyz[0] + xyz[1] + xyz[2];
                if xyz[1] < DARK_Y || s <= 0.0 {
                    acc.dark += 1;
                    continue;
                }
                let xy = [xyz[0] / s, xyz[1] / s];
                for (k, g) in gamuts.iter().enumerate() {
                    acc.outside[k] += u64::from(!inside_gamut(g, xy));
                }
                let bin = |v: f64| ((v * BINS as f64) as usize).min(BINS - 1);
                let idx = bin(xy[1]) * BINS + bin(xy[0]);
                acc.counts[idx] += 1;
                let sum = &mut acc.sums[idx];
                for k in 0..3 {
                    sum[k] += f32::from(t[k]) / 255.0;
                }
            }
            acc
        })
        .reduce_with(Partial::merge)
        .unwrap_or_else(|| Partial {
            counts: vec![0; BINS * BINS],
            sums: vec![[0.0; 3]; BINS * BINS],
            dark: 0,
            outside: vec![0; gamuts.len()],
        });
    let total = image.texels.len() as u64;
    let lit = total - part.dark;
    PixelReport {
        name: image.name.clone(),
        total,
        dark: part.dark,
        counts: part.counts,
        colour_sums: part.sums,
        outside: gamuts
            .iter()
            .zip(&part.outside)
            .map(|(g, &n)| {
                (
                    g.name.clone(),
                    if lit == 0 { 0.0 } else { n as f64 / lit as f64 },
                )
            })
            .collect(),
    }
}

struct Partial {
    counts: Vec<u32>,
    sums: Vec<[f32; 3]>,
    dark: u64,
    outside: Vec<u64>,
}

impl Partial {
    fn merge(mut self, other: Self) -> Self {
        for (a, b) in self.counts.iter_mut().zip(&other.counts) {
            *a = a.saturating_add(*b);
        }
        for (a, b) in self.sums.iter_mut().zip(&other.sums) {
            for k in 0..3 {
                a[k] += b[k];
            }
        }
        self.dark += other.dark;
        for (a, b) in self.outside.iter_mut().zip(&other.outside) {
            *a += b;
        }
        self
    }
}

impl PixelReport {
    /// The occupied bins: (xy of the bin centre, pixel count, mean encoded sRGB).
    pub fn occupied(&self) -> impl Iterator<Item = ([f64; 2], u32, [f32; 3])> + '_ {
        self.counts
            .iter()
            .enumerate()
            .filter(|(_, &n)| n > 0)
            .map(|(i, &n)| {
                let (x, y) = (i % BINS, i / BINS);
                let xy = [
                    (x as f64 + 0.5) / BINS as f64,
                    (y as f64 + 0.5) / BINS as f64,
                ];
                let s = self.colour_sums[i];
                let n_f = n as f32;
                (xy, n, [s[0] / n_f, s[1] / n_f, s[2] / n_f])
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(texels: Vec<[u8; 4]>, width: u32) -> Texture {
        let height = texels.len() as u32 / width;
        Texture::new("test", width, height, texels, true).unwrap()
    }

    #[test]
    fn primaries_are_inside_srgb_and_fractions_are_counted() {
        let img = image(
            vec![
                [255, 0, 0, 255],
                [0, 255, 0, 255],
                [0, 0, 255, 255],
                [0, 0, 0, 255],
                [128, 128, 128, 255],
                [255, 255, 255, 255],
            ],
            3,
        );
        let srgb = RgbSpace::srgb();
        // A gamut that holds only the neutral colours: the three primaries fall outside.
        let tiny = RgbSpace::new(
            "tiny",
            [[0.35, 0.3], [0.3, 0.4], [0.28, 0.3]],
            [0.3127, 0.329],
            "D65",
            crate::color::Transfer::Srgb,
        )
        .unwrap();
        let r = analyse(&img, &[srgb, tiny]);
        assert_eq!((r.total, r.dark), (6, 1));
        assert_eq!(r.outside[0], ("sRGB".to_owned(), 0.0));
        assert!(
            (r.outside[1].1 - 3.0 / 5.0).abs() < 1e-12,
            "{:?}",
            r.outside
        );
        assert_eq!(r.counts.iter().map(|&c| u64::from(c)).sum::<u64>(), 5);
        let grey: Vec<_> = r.occupied().filter(|(_, n, _)| *n == 2).collect();
        assert_eq!(grey.len(), 1, "grey and white share the D65 bin");
        let (xy, _, c) = grey[0];
        assert!(
            (xy[0] - 0.3127).abs() < 1.0 / BINS as f64 && (xy[1] - 0.329).abs() < 1.0 / BINS as f64
        );
        assert!((c[0] - (128.0 / 255.0 + 1.0) / 2.0).abs() < 1e-6, "{c:?}");
    }
}
