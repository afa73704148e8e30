//! Render targets. [`Target`] is the tiled working form the fill loop writes (each 64x64
//! tile owns its colour and depth, so tiles are filled in parallel without sharing memory);
//! [`Framebuffer`] is the resolved, row-major image.
//!
//! Colour is linear-light RGBA in f32; depth is f32 reversed-Z (1 = near plane, 0 = far
//! plane, cleared to 0, nearer wins with `>`).
//!
//! Multisampling: a target of 4 samples per pixel stores colour and depth per sample, at the
//! positions of [`sample_offsets`]; the fill tests coverage and depth per sample and shades
//! once per pixel and triangle. Every read of a pixel's colour ([`Tile::color_at`], the
//! encoders, [`Target::resolve`]) is the average of its samples in linear light, and every
//! read of its depth the nearest of them (what picking wants at a silhouette).

use glam::Vec4;
use rayon::prelude::*;

mod readout;

/// Tile edge in pixels.
pub const TILE: u32 = 64;
pub(crate) const TILE_PIXELS: usize = (TILE * TILE) as usize;

/// The sample counts a target supports.
pub const SAMPLE_COUNTS: [u32; 2] = [1, 4];

/// Direct3D's standard 4-sample pattern, in 1/16 pixel from the pixel centre (x right, y
/// down): a rotated grid, four distinct x and four distinct y, so near-vertical and
/// near-horizontal edges get four coverage levels where an ordered 2x2 grid gives two.
const MSAA4: [[i32; 2]; 4] = [[-2, -6], [6, -2], [-6, 2], [2, 6]];

/// How far the samples of a pixel lie from its centre along x or y at most, in fixed-point
/// units (1/256 pixel), with `samples` per pixel.
#[must_use]
#[inline(always)]
pub(crate) fn sample_reach(samples: u32) -> i64 {
    if samples == 1 {
        return 0;
    }
    let most = sample_offsets(samples)
        .iter()
        .flat_map(|o| [o[0].abs(), o[1].abs()])
        .max()
        .unwrap_or(0);
    i64::from(most) * (super::setup::ONE / 16)
}

/// Sample positions of a target with `samples` per pixel, in 1/16 pixel from the pixel
/// centre; one sample is the centre itself.
#[must_use]
pub fn sample_offsets(samples: u32) -> &'static [[i32; 2]] {
    if samples == 4 {
        &MSAA4
    } else {
        &[[0, 0]]
    }
}

/// One tile: pixels `x0..x0 + w` by `y0..y0 + h` of the image (w, h <= 64 at the right and
/// bottom borders). Storage is always 64x64 per sample, row stride 64.
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
    /// Linear RGBA as four planes of 64x64 per sample (red, green, blue, alpha: channel `c`
    /// of sample `s` at `(4 s + c) * 4096`), so the fill reads and writes eight pixels of one
    /// channel at once; stale while `pending_clear` is set. Read and written through
    /// [`Tile::color_at`], [`Tile::set_color`] and [`Tile::planes_mut`].
    color: Vec<f32>,
    /// Reversed-Z depth, one 64x64 plane per sample; stale while `pending_clear` is set.
    pub depth: Vec<f32>,
    /// `Some(c)`: the tile is logically cleared to colour `c` and depth 0.
    pub pending_clear: Option<Vec4>,
    /// Samples per pixel (one of [`SAMPLE_COUNTS`]).
    samples: u32,
}

impl Tile {
    /// A tile at the origin with zeroed storage for `samples` per pixel (placed by
    /// [`Target::reshape`]).
    fn blank(samples: u32) -> Self {
        let n = samples as usize;
        Self {
            x0: 0,
            y0: 0,
            w: TILE,
            h: TILE,
            color: vec![0.0; 4 * n * TILE_PIXELS],
            depth: vec![0.0; n * TILE_PIXELS],
            pending_clear: None,
            samples,
        }
    }

    /// Samples per pixel.
    #[inline(always)]
    #[must_use]
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// The tile's storage (colour planes, depth), for the fill.
    #[inline(always)]
    pub(crate) fn planes_mut(&mut self) -> (&mut [f32], &mut [f32]) {
        (&mut self.color, &mut self.depth)
    }

    /// Sets the colour of (every sample of) the pixel at storage offset `o` (the tile must
    /// be materialised).
    #[inline]
    pub fn set_color(&mut self, o: usize, c: Vec4) {
        for s in 0..self.samples as usize {
            let p = &mut self.color[4 * s * TILE_PIXELS + o..];
            p[0] = c.x;
            p[TILE_PIXELS] = c.y;
            p[2 * TILE_PIXELS] = c.z;
            p[3 * TILE_PIXELS] = c.w;
        }
    }

    /// Stored colour at offset `o` (the average of its samples), ignoring a pending clear.
    #[inline]
    fn stored(&self, o: usize) -> Vec4 {
        let sample = |s: usize| {
            let p = &self.color[4 * s * TILE_PIXELS + o..];
            Vec4::new(p[0], p[TILE_PIXELS], p[2 * TILE_PIXELS], p[3 * TILE_PIXELS])
        };
        if self.samples == 1 {
            return sample(0);
        }
        let sum = (0..self.samples as usize).fold(Vec4::ZERO, |a, s| a + sample(s));
        sum / self.samples as f32
    }

    /// Stored depth at offset `o` (the nearest of its samples), ignoring a pending clear.
    #[inline]
    fn stored_depth(&self, o: usize) -> f32 {
        nearest(&self.depth, o)
    }

    /// Raises the depth of every sample of the pixel at offset `o` to at least `z` (the tile
    /// must be materialised).
    #[inline]
    pub fn raise_depth(&mut self, o: usize, z: f32) {
        for d in self.depth[o..].iter_mut().step_by(TILE_PIXELS) {
            *d = d.max(z);
        }
    }

    /// Applies a pending clear, so `color` and `depth` hold the tile's contents.
    #[inline]
    pub fn materialize(&mut self) {
        if let Some(c) = self.pending_clear.take() {
            let c = c.to_array();
            for (i, plane) in self.color.chunks_exact_mut(TILE_PIXELS).enumerate() {
                plane.fill(c[i % 4]);
            }
            self.depth.fill(0.0);
        }
    }

    /// Colour of the pixel at storage offset `o`.
    #[inline]
    #[must_use]
    pub fn color_at(&self, o: usize) -> Vec4 {
        self.pending_clear.unwrap_or_else(|| self.stored(o))
    }

    /// Depth of the pixel at storage offset `o`.
    #[inline]
    #[must_use]
    pub fn depth_at(&self, o: usize) -> f32 {
        if self.pending_clear.is_some() {
            0.0
        } else {
            self.stored_depth(o)
        }
    }
}

/// The nearest (largest, reversed-Z) of the sample depths at offset `o` of a tile's depth
/// planes.
#[inline]
fn nearest(depth: &[f32], o: usize) -> f32 {
    depth[o..]
        .iter()
        .step_by(TILE_PIXELS)
        .copied()
        .reduce(f32::max)
        .unwrap_or(0.0)
}

/// The tiled render target.
#[derive(Clone, Debug)]
pub struct Target {
    pub width: u32,
    pub height: u32,
    pub tiles_x: u32,
    pub tiles_y: u32,
    /// Row-major, `tiles_x * tiles_y` tiles.
    pub tiles: Vec<Tile>,
    /// Tiles kept from a larger size, reused when the target grows again.
    spare: Vec<Tile>,
    /// Samples per pixel (one of [`SAMPLE_COUNTS`]).
    samples: u32,
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
                    pending_clear: Some(clear),
                    ..Tile::blank(1)
                }
            })
            .collect();
        Self {
            width,
            height,
            tiles_x,
            tiles_y,
            tiles,
            spare: Vec::new(),
            samples: 1,
        }
    }

    /// Samples per pixel.
    #[must_use]
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Sets the samples per pixel: 1, or 4 (multisampling; see the module docs). Any other
    /// count is rounded to the nearest of these. A change reallocates the tiles and clears
    /// the target to `clear`; the same count again does nothing.
    pub fn set_samples(&mut self, samples: u32, clear: Vec4) {
        let samples = if samples >= 3 { 4 } else { 1 };
        if samples == self.samples {
            return;
        }
        self.samples = samples;
        self.spare.clear();
        for t in &mut self.tiles {
            *t = Tile {
                pending_clear: Some(clear),
                ..Tile {
                    x0: t.x0,
                    y0: t.y0,
                    w: t.w,
                    h: t.h,
                    ..Tile::blank(samples)
                }
            };
        }
    }

    /// How far, in fixed-point units (1/256 pixel), the samples lie from the pixel centre
    /// along x or y at most: what set-up, binning and block classification widen their
    /// pixel bounds by.
    #[must_use]
    pub(crate) fn reach(&self) -> i64 {
        sample_reach(self.samples)
    }

    /// Makes this a `width` x `height` target (each at least 1) cleared to `clear`, keeping
    /// its tile memory: switching between sizes it has had before allocates nothing.
    pub fn reshape(&mut self, width: u32, height: u32, clear: Vec4) {
        let (width, height) = (width.max(1), height.max(1));
        if (self.width, self.height) != (width, height) {
            let tiles_x = width.div_ceil(TILE);
            let tiles_y = height.div_ceil(TILE);
            let n = (tiles_x * tiles_y) as usize;
            while self.tiles.len() > n {
                if let Some(t) = self.tiles.pop() {
                    self.spare.push(t);
                }
            }
            while self.tiles.len() < n {
                let samples = self.samples;
                self.tiles
                    .push(self.spare.pop().unwrap_or_else(|| Tile::blank(samples)));
            }
            for (i, t) in self.tiles.iter_mut().enumerate() {
                let (tx, ty) = (i as u32 % tiles_x, i as u32 / tiles_x);
                (t.x0, t.y0) = (tx * TILE, ty * TILE);
                t.w = TILE.min(width - t.x0);
                t.h = TILE.min(height - t.y0);
            }
            (self.width, self.height, self.tiles_x, self.tiles_y) =
                (width, height, tiles_x, tiles_y);
        }
        self.clear(clear);
    }

    /// Clears colour to `clear` and depth to 0 (far). Lazy: a tile is filled only when
    /// something is first drawn into it.
    pub fn clear(&mut self, clear: Vec4) {
        for t in &mut self.tiles {
            t.pending_clear = Some(clear);
        }
    }

    /// Clears depth to 0 (far) and every pixel's colour to `f(x, y)` (pixel centre at
    /// `(x + 0.5, y + 0.5)`; every sample of the pixel gets it), in parallel over tiles:
    /// a background that varies over the image, such as an environment.
    pub fn clear_with(&mut self, f: impl Fn(u32, u32) -> Vec4 + Sync) {
        self.tiles.par_iter_mut().for_each(|t| {
            t.pending_clear = Some(Vec4::ZERO);
            t.materialize();
            for y in 0..t.h {
                for x in 0..t.w {
                    let o = (y * TILE + x) as usize;
                    t.set_color(o, f(t.x0 + x, t.y0 + y));
                }
            }
        });
    }

    /// Replaces every stored colour (each sample of each pixel, and a pending clear colour)
    /// by `f(colour)`, in parallel over tiles: a per-pixel operator such as tone mapping,
    /// applied before samples are averaged.
    pub fn map_colors(&mut self, f: impl Fn(Vec4) -> Vec4 + Sync) {
        self.tiles.par_iter_mut().for_each(|t| {
            if let Some(c) = t.pending_clear.as_mut() {
                *c = f(*c);
                return;
            }
            for plane in t.color.chunks_exact_mut(4 * TILE_PIXELS) {
                let (r, rest) = plane.split_at_mut(TILE_PIXELS);
                let (g, rest) = rest.split_at_mut(TILE_PIXELS);
                let (b, a) = rest.split_at_mut(TILE_PIXELS);
                for i in 0..TILE_PIXELS {
                    let c = f(Vec4::new(r[i], g[i], b[i], a[i]));
                    (r[i], g[i], b[i], a[i]) = (c.x, c.y, c.z, c.w);
                }
            }
        });
    }

    /// Clears depth to 0 (far), leaving colour as it is.
    pub fn clear_depth(&mut self) {
        self.tiles
            .par_iter_mut()
            .filter(|t| t.pending_clear.is_none())
            .for_each(|t| t.depth.fill(0.0));
    }

    /// Copies the depth plane into `copy`, for a pass that must test against a depth buffer
    /// it may not change (wireframe's hidden-line pass). Lazily cleared tiles are not copied.
    /// Reuses `copy`'s memory.
    pub fn save_depth(&self, copy: &mut DepthCopy) {
        // Grown to the largest tile count seen, never shrunk: entries past this target's
        // tiles are ignored (the zips below stop at the shorter side).
        if copy.0.len() < self.tiles.len() {
            copy.0.resize_with(self.tiles.len(), || SavedTile {
                cleared: None,
                depth: Vec::new(),
            });
        }
        copy.0
            .par_iter_mut()
            .zip(self.tiles.par_iter())
            .for_each(|(s, t)| {
                // Sized as the tile's (its sample count) even when stale: restoring swaps it in.
                s.cleared = t.pending_clear;
                s.depth.resize(t.depth.len(), 0.0);
                if t.pending_clear.is_none() {
                    s.depth.copy_from_slice(&t.depth);
                }
            });
    }

    /// Puts the depth saved by [`Target::save_depth`] back, leaving in `copy` the depth the
    /// target had (the scratch depth drawn since the save), by swapping buffers. Tiles
    /// cleared before and untouched since stay lazy; tiles cleared before and touched since
    /// must not have had colour written.
    pub fn restore_depth(&mut self, copy: &mut DepthCopy) {
        for (t, s) in self.tiles.iter_mut().zip(&mut copy.0) {
            match (s.cleared, t.pending_clear) {
                (None, _) => {
                    t.materialize();
                    std::mem::swap(&mut t.depth, &mut s.depth);
                }
                (Some(_), Some(_)) => {}
                (Some(c), None) => {
                    std::mem::swap(&mut t.depth, &mut s.depth);
                    t.pending_clear = Some(c);
                    s.cleared = None;
                }
            }
        }
    }
}

/// One tile of a [`DepthCopy`].
#[derive(Clone, Debug)]
struct SavedTile {
    /// `Some(c)`: the tile was lazily cleared (depth 0 everywhere) to colour `c`, and
    /// `depth` is stale.
    cleared: Option<Vec4>,
    depth: Vec<f32>,
}

/// A copy of a target's depth plane, tile by tile, reused from frame to frame.
#[derive(Clone, Debug, Default)]
pub struct DepthCopy(Vec<SavedTile>);

impl DepthCopy {
    /// Depth at storage offset `o` of tile `t` (the nearest of its samples; 0 in a cleared
    /// tile).
    #[inline]
    #[must_use]
    pub fn at(&self, t: usize, o: usize) -> f32 {
        let s = &self.0[t];
        if s.cleared.is_some() {
            0.0
        } else {
            nearest(&s.depth, o)
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
        let lut = crate::color::Srgb8Table::get();
        let mut out = Vec::with_capacity(self.color.len() * 3);
        for c in &self.color {
            for v in [c.x, c.y, c.z] {
                out.push(lut.encode(v));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests;
