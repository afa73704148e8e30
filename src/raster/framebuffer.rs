//! Render targets. [`Target`] is the tiled working form the fill loop writes (each 64x64
//! tile owns its colour and depth, so tiles are filled in parallel without sharing memory);
//! [`Framebuffer`] is the resolved, row-major image.
//!
//! Colour is linear-light RGBA in f32; depth is f32 reversed-Z (1 = near plane, 0 = far
//! plane, cleared to 0, nearer wins with `>`).

use glam::Vec4;
use rayon::prelude::*;

/// Tile edge in pixels.
pub const TILE: u32 = 64;
const TILE_PIXELS: usize = (TILE * TILE) as usize;

/// One tile: pixels `x0..x0 + w` by `y0..y0 + h` of the image (w, h <= 64 at the right and
/// bottom borders). Storage is always 64x64, row stride 64.
///
/// Clearing is lazy: a cleared tile only records its clear colour, and its storage is filled
/// the first time something is drawn into it ([`Tile::materialize`]), so tiles no geometry
/// touches cost nothing per frame.
#[derive(Clone, Debug)]
pub struct Tile {
    pub x0: u32,
    pub y0: u32,
    pub w: u32,
    pub h: u32,
    /// Linear RGBA; stale while `pending_clear` is set.
    pub color: Vec<Vec4>,
    /// Reversed-Z depth; stale while `pending_clear` is set.
    pub depth: Vec<f32>,
    /// `Some(c)`: the tile is logically cleared to colour `c` and depth 0.
    pub pending_clear: Option<Vec4>,
}

impl Tile {
    /// Applies a pending clear, so `color` and `depth` hold the tile's contents.
    #[inline]
    pub fn materialize(&mut self) {
        if let Some(c) = self.pending_clear.take() {
            self.color.fill(c);
            self.depth.fill(0.0);
        }
    }

    /// Colour of the pixel at storage offset `o`.
    #[inline]
    #[must_use]
    pub fn color_at(&self, o: usize) -> Vec4 {
        self.pending_clear.unwrap_or(self.color[o])
    }

    /// Depth of the pixel at storage offset `o`.
    #[inline]
    #[must_use]
    pub fn depth_at(&self, o: usize) -> f32 {
        if self.pending_clear.is_some() {
            0.0
        } else {
            self.depth[o]
        }
    }
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
            .into_par_iter()
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
                    pending_clear: None,
                }
            })
            .collect();
        Self {
            width,
            height,
            tiles_x,
            tiles_y,
            tiles,
        }
    }

    /// Clears colour to `clear` and depth to 0 (far). Lazy: see [`Tile`].
    pub fn clear(&mut self, clear: Vec4) {
        for t in &mut self.tiles {
            t.pending_clear = Some(clear);
        }
    }

    /// 8-bit sRGB-encoded RGB, row-major, straight from the tiles (in parallel over tile
    /// rows); out-of-range values are clamped and NaN becomes 0.
    #[must_use]
    pub fn to_srgb8(&self) -> Vec<u8> {
        let lut = encode_table();
        let row_bytes = self.width as usize * 3;
        let mut out = vec![0u8; row_bytes * self.height as usize];
        out.par_chunks_mut(row_bytes * TILE as usize)
            .enumerate()
            .for_each(|(ty, band)| {
                for t in &self.tiles[ty * self.tiles_x as usize..(ty + 1) * self.tiles_x as usize] {
                    let clear = t
                        .pending_clear
                        .map(|c| [encode(lut, c.x), encode(lut, c.y), encode(lut, c.z)]);
                    for y in 0..t.h as usize {
                        let dst =
                            &mut band[y * row_bytes + t.x0 as usize * 3..][..t.w as usize * 3];
                        match clear {
                            Some(rgb) => dst
                                .chunks_exact_mut(3)
                                .for_each(|px| px.copy_from_slice(&rgb)),
                            None => {
                                let src = &t.color[y * TILE as usize..][..t.w as usize];
                                for (px, c) in dst.chunks_exact_mut(3).zip(src) {
                                    px[0] = encode(lut, c.x);
                                    px[1] = encode(lut, c.y);
                                    px[2] = encode(lut, c.z);
                                }
                            }
                        }
                    }
                }
            });
        out
    }

    /// Index of the tile holding pixel (x, y), and the pixel's offset inside it.
    #[inline]
    #[must_use]
    pub fn locate(&self, x: u32, y: u32) -> (usize, usize) {
        let t = (y / TILE) * self.tiles_x + x / TILE;
        let o = (y % TILE) * TILE + x % TILE;
        (t as usize, o as usize)
    }

    /// Takes a copy of the depth plane, for a pass that must test against a depth buffer it
    /// may not change (wireframe's hidden-line pass). Lazily cleared tiles are not copied.
    #[must_use]
    pub fn save_depth(&self) -> DepthCopy {
        DepthCopy(
            self.tiles
                .par_iter()
                .map(|t| match t.pending_clear {
                    Some(c) => SavedTile::Cleared(c),
                    None => SavedTile::Depth(t.depth.clone()),
                })
                .collect(),
        )
    }

    /// Puts a saved depth plane back and returns the depth the target had (the scratch depth
    /// drawn since [`Target::save_depth`]). Tiles cleared before and untouched since stay lazy;
    /// tiles cleared before and touched since must not have had colour written.
    pub fn restore_depth(&mut self, saved: DepthCopy) -> DepthCopy {
        let scratch = self
            .tiles
            .iter_mut()
            .zip(saved.0)
            .map(|(t, saved)| match (saved, t.pending_clear) {
                (SavedTile::Depth(d), _) => {
                    t.materialize();
                    SavedTile::Depth(std::mem::replace(&mut t.depth, d))
                }
                (SavedTile::Cleared(c), Some(_)) => SavedTile::Cleared(c),
                (SavedTile::Cleared(c), None) => {
                    t.pending_clear = Some(c);
                    SavedTile::Depth(std::mem::replace(&mut t.depth, vec![0.0; TILE_PIXELS]))
                }
            })
            .collect();
        DepthCopy(scratch)
    }

    /// Resolves the tiles into a row-major framebuffer.
    #[must_use]
    pub fn resolve(&self) -> Framebuffer {
        let n = self.width as usize * self.height as usize;
        let mut fb = Framebuffer {
            width: self.width,
            height: self.height,
            color: vec![Vec4::ZERO; n],
            depth: vec![0.0; n],
        };
        for t in &self.tiles {
            for y in 0..t.h {
                let src = (y * TILE) as usize;
                let dst = ((t.y0 + y) * self.width + t.x0) as usize;
                let w = t.w as usize;
                match t.pending_clear {
                    Some(c) => {
                        fb.color[dst..dst + w].fill(c);
                        fb.depth[dst..dst + w].fill(0.0);
                    }
                    None => {
                        fb.color[dst..dst + w].copy_from_slice(&t.color[src..src + w]);
                        fb.depth[dst..dst + w].copy_from_slice(&t.depth[src..src + w]);
                    }
                }
            }
        }
        fb
    }
}

/// One tile of a [`DepthCopy`].
#[derive(Clone, Debug)]
enum SavedTile {
    /// The tile was lazily cleared (depth 0 everywhere) to this colour.
    Cleared(Vec4),
    Depth(Vec<f32>),
}

/// A copy of a target's depth plane, tile by tile.
#[derive(Clone, Debug)]
pub struct DepthCopy(Vec<SavedTile>);

impl DepthCopy {
    /// Depth at storage offset `o` of tile `t` (0 in a cleared tile).
    #[inline]
    #[must_use]
    pub fn at(&self, t: usize, o: usize) -> f32 {
        match &self.0[t] {
            SavedTile::Cleared(_) => 0.0,
            SavedTile::Depth(d) => d[o],
        }
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

const ENCODE_STEPS: usize = 16384;

/// Linear -> sRGB byte through a 16384-entry table indexed by the rounded linear value:
/// within one code value of the exact transfer everywhere (the table step is 1/16384, and
/// sRGB's steepest slope, 12.92 * 255 codes per unit at 0, moves 0.2 codes per step).
fn encode_table() -> &'static [u8; ENCODE_STEPS + 1] {
    static TABLE: std::sync::OnceLock<[u8; ENCODE_STEPS + 1]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        std::array::from_fn(|i| {
            (crate::texture::linear_to_srgb(i as f32 / ENCODE_STEPS as f32) * 255.0 + 0.5) as u8
        })
    })
}

#[inline(always)]
fn encode(lut: &[u8; ENCODE_STEPS + 1], v: f32) -> u8 {
    // `as usize` saturates and maps NaN to 0; the clamp bounds the index.
    lut[((v * ENCODE_STEPS as f32 + 0.5) as usize).min(ENCODE_STEPS)]
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
        t.tiles[ti].materialize();
        t.tiles[ti].color[o] = Vec4::ZERO;
        let fb = t.resolve();
        assert_eq!(fb.pixel(69, 64), Vec4::ZERO);
        assert_eq!(fb.pixel(68, 64), Vec4::ONE);
        t.clear(Vec4::splat(0.5));
        assert_eq!(t.resolve().pixel(69, 64), Vec4::splat(0.5));
        assert_eq!(t.to_srgb8()[(64 * 70 + 69) * 3], 188);
    }
}
