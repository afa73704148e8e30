//! [`LinearImage`]: linear-light RGB in f64, the currency of references and metrics.

use crate::raster::Framebuffer;

/// A linear-light RGB image in f64, row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearImage {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<[f64; 3]>,
}

impl LinearImage {
    /// A `width` x `height` image of one colour.
    #[must_use]
    pub fn filled(width: u32, height: u32, c: [f64; 3]) -> Self {
        Self {
            width,
            height,
            rgb: vec![c; width as usize * height as usize],
        }
    }

    /// The colour of a rendered frame (alpha dropped).
    #[must_use]
    pub fn from_framebuffer(fb: &Framebuffer) -> Self {
        Self {
            width: fb.width,
            height: fb.height,
            rgb: fb
                .color
                .iter()
                .map(|c| [f64::from(c.x), f64::from(c.y), f64::from(c.z)])
                .collect(),
        }
    }

    /// Box-filters `factor` x `factor` blocks into one pixel (supersampling resolve);
    /// the size must be a multiple of `factor`.
    #[must_use]
    pub fn downsample(&self, factor: u32) -> Self {
        let f = factor.max(1);
        let (w, h) = (self.width / f, self.height / f);
        let mut rgb = vec![[0.0; 3]; w as usize * h as usize];
        let n = f64::from(f * f);
        for y in 0..h {
            for x in 0..w {
                let mut sum = [0.0; 3];
                for j in 0..f {
                    for i in 0..f {
                        let p = self.rgb[((y * f + j) * self.width + x * f + i) as usize];
                        for k in 0..3 {
                            sum[k] += p[k];
                        }
                    }
                }
                rgb[(y * w + x) as usize] = sum.map(|s| s / n);
            }
        }
        Self {
            width: w,
            height: h,
            rgb,
        }
    }

    /// 8-bit encoded sRGB (clamped), RGB interleaved.
    #[must_use]
    pub fn to_srgb8(&self) -> Vec<u8> {
        self.rgb
            .iter()
            .flat_map(|c| c.map(crate::color::srgb8_f64))
            .collect()
    }
}
