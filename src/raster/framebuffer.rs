//! Render targets. [`Target`] is the tiled working form the fill loop writes (each 64x64
//! tile owns its colour and depth, so tiles are filled in parallel without sharing memory);
//! [`Framebuffer`] is the resolved, row-major image.
//!
//! Colour is linear-light RGBA in f32; depth is f32 reversed-Z (1 = near plane, 0 = far
//! plane, cleared to 0, nearer wins with `>`).

use glam::Vec4;

/// Tile edge in pixels.
pub const TILE: u32 = 64;
const TILE_PIXELS: usize = (TILE * TILE) as usize;

/// One tile: pixels `x0..x0 + w` by `y0..y0 + h` of the image (w, h <= 64 at the right and
/// bottom borders). Storage is always 64x64, row stride 64.
#[derive(Clone, Debug)]
pub struct Tile {
    pub x0: u32,
    pub y0: u32,
    pub w: u32,
    pub h: u32,
    pub color: Vec<Vec4>,
    pub depth: Vec<f32>,
}

/// The tiled render target.
#[derive(Clone, Debug)]
pub struct Target {
    pub width: u32,
    pub height: u32,
    pub tiles_x: u32,
    pub tiles_y: u32,
    pub tiles: Vec<Tile>,
}

impl Target {
    /// A target of `width` x `height` pixels (each at least 1) cleared to `clear` and depth 0.
    #[must_use]
    pub fn new(width: u32, height: u32, clear: Vec4) -> Self {
        let (width, height) = (width.max(1), height.max(1));
        let tiles_x = width.div_ceil(TILE);
        let tiles_y = height.div_ceil(TILE);
        let tiles = (0..tiles_x * tiles_y)
            .map(|i| {
                let (tx, ty) = (i % tiles_x, i / tiles_x);
                let (x0, y0) = (tx * TILE, ty * TILE);
                Tile {
                    x0,
                    y0,
                    w: TILE.min(width - x0),
                    h: TILE.min(height - y0),
                    color: vec![clear; TILE_PIXELS],
                    depth: vec![0.0; TILE_PIXELS],
                }
            })
            .collect();
        Self { width, height, tiles_x, tiles_y, tiles }
    }

    /// Index of the tile holding pixel (x, y), and the pixel's offset inside it.
    #[inline]
    #[must_use]
    pub fn locate(&self, x: u32, y: u32) -> (usize, usize) {
        let t = (y / TILE) * self.tiles_x + x / TILE;
        let o = (y % TILE) * TILE + x % TILE;
        (t as usize, o as usize)
    }

    /// Copies the depth of every tile (for passes that test against a scratch depth).
    #[must_use]
    pub fn depths(&self) -> Vec<Vec<f32>> {
        self.tiles.iter().map(|t| t.depth.clone()).collect()
    }

    /// Resolves the tiles into a row-major framebuffer.
    #[must_use]
    pub fn resolve(&self) -> Framebuffer {
        let n = self.width as usize * self.height as usize;
        let mut fb = Framebuffer { width: self.width, height: self.height, color: vec![Vec4::ZERO; n], depth: vec![0.0; n] };
        for t in &self.tiles {
            for y in 0..t.h {
                let src = (y * TILE) as usize;
                let dst = ((t.y0 + y) * self.width + t.x0) as usize;
                let w = t.w as usize;
                fb.color[dst..dst + w].copy_from_slice(&t.color[src..src + w]);
                fb.depth[dst..dst + w].copy_from_slice(&t.depth[src..src + w]);
            }
        }
        fb
    }
}

/// A resolved image: row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Framebuffer {
    pub width: u32,
    pub height: u32,
    /// Linear-light RGBA.
    pub color: Vec<Vec4>,
    /// Reversed-Z depth, 0 where nothing was drawn.
    pub depth: Vec<f32>,
}

impl Framebuffer {
    /// Colour at (x, y).
    ///
    /// # Panics
    /// If (x, y) is outside the image.
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> Vec4 {
        self.color[(y * self.width + x) as usize]
    }

    /// 8-bit sRGB-encoded RGB, row-major (out-of-range values are clamped; NaN becomes 0).
    #[must_use]
    pub fn to_srgb8(&self) -> Vec<u8> {
        let lut = encode_table();
        let mut out = Vec::with_capacity(self.color.len() * 3);
        for c in &self.color {
            for v in [c.x, c.y, c.z] {
                out.push(encode(lut, v));
            }
        }
        out
    }
}

const ENCODE_STEPS: usize = 4096;

/// Linear -> sRGB byte through a 4096-entry table indexed by the linear value (exact to
/// within one code value; sRGB's steep toe below 1/4096 is computed exactly).
fn encode_table() -> &'static [u8; ENCODE_STEPS + 1] {
    static TABLE: std::sync::OnceLock<[u8; ENCODE_STEPS + 1]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        std::array::from_fn(|i| (crate::texture::linear_to_srgb(i as f32 / ENCODE_STEPS as f32) * 255.0 + 0.5) as u8)
    })
}

#[inline]
fn encode(lut: &[u8; ENCODE_STEPS + 1], v: f32) -> u8 {
    if v.is_nan() || v <= 0.0 {
        0
    } else if v >= 1.0 {
        255
    } else if v < 16.0 / ENCODE_STEPS as f32 {
        (crate::texture::linear_to_srgb(v) * 255.0 + 0.5) as u8
    } else {
        lut[(v * ENCODE_STEPS as f32 + 0.5) as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encode_matches_exact_transfer() {
        for i in 0..=10_000 {
            let v = i as f32 / 10_000.0;
            let exact = (crate::texture::linear_to_srgb(v) * 255.0 + 0.5) as i32;
            let got = i32::from(encode(encode_table(), v));
            assert!((exact - got).abs() <= 1, "{v}: {exact} vs {got}");
        }
        assert_eq!(encode(encode_table(), f32::NAN), 0);
        assert_eq!(encode(encode_table(), 7.0), 255);
    }

    #[test]
    fn resolve_odd_size() {
        let mut t = Target::new(70, 65, Vec4::ONE);
        let (ti, o) = t.locate(69, 64);
        t.tiles[ti].color[o] = Vec4::ZERO;
        let fb = t.resolve();
        assert_eq!(fb.pixel(69, 64), Vec4::ZERO);
        assert_eq!(fb.pixel(68, 64), Vec4::ONE);
    }
}
