//! The tiled rasterizer: clip-space transform, frustum and back-face culling, near/far and
//! guard-band clipping in homogeneous space, fixed-point triangle setup, binning into 64x64
//! tiles, and per-tile fill with a depth test, run in parallel over tiles.
//!
//! The rasterizer knows no materials, lights or UI. A draw's vertices carry a run-time number
//! of float varyings ([`Draw::stride`], at most [`MAX_VARYINGS`]); set-up stores them per
//! triangle and the fill interpolates them eight pixels (one block row, a "group") at a time
//! into [`Batch`]es of up to [`GROUPS`] groups, which a [`FragmentShader`] shades together.
//! The fill of a tile is compiled once per kernel (portable, AVX2, AVX-512, chosen once at run
//! time: `realist_simd::kernel`); it calls the shader through `dyn` once per batch, and the
//! shader runs its own per-kernel stages, so no function holds both the fill and a shader.
//!
//! Phases of one pass ([`draw`]):
//! 1. *setup and binning* (parallel over chunks of 2048 consecutive input triangles, across
//!    draws): trivial frustum reject, clipping where a vertex is outside the near or far plane
//!    or the guard band, perspective divide, snapping to 1/256 pixel, culling, edge
//!    equations, and each set-up triangle appended to its chunk's list for every 64x64 tile
//!    its bounding box touches and its edges do not exclude;
//! 2. *fill* (parallel over tiles, each task owns its tile's colour and depth): the tile's
//!    lists in chunk order, so triangles are drawn in submission order and 1 and N threads
//!    produce bit-identical images.
//!
//! Triangles are processed in batches so memory stays bounded on multi-million-triangle meshes.
//! [`draw_list`] takes the pipeline's working memory ([`Bins`], [`RasterScratch`]) from the
//! caller, so a renderer that keeps it allocates nothing per frame (clipping works on
//! fixed-size polygons on the stack); it also records per-tile cost ([`TileCost`]) and
//! can be stopped between tiles.
//!
//! Rejected designs: a scanline rasterizer (not tile-parallel, fill rule harder to make exact);
//! float edge functions (shared edges can crack or double-cover); serial binning into one
//! list per tile (on a million-triangle mesh the copy into one list took longer than the
//! parallel setup it followed); a type per combination of varyings (every new attribute
//! doubled the compiled shaders).

// The crates below this one, under the module names the code uses (`crate::scene::...`).
use realist_color as color;
use realist_geom as geom;
use realist_simd as simd;

mod clip;
mod fill;
mod framebuffer;
mod line;
mod pipeline;
mod setup;
pub mod stages;

use crate::simd::{Lane, Level, F8, LANES};

use framebuffer::Tile;

pub use clip::MAX_SECTIONS;
pub use framebuffer::{sample_offsets, DepthCopy, Framebuffer, Target, SAMPLE_COUNTS, TILE};
pub use line::{draw_lines, draw_points, draw_wide_lines, LineStyle, StrokeStyle, MAX_STROKE_PX};
pub use pipeline::{
    draw, draw_list, draw_with_kernel, transform_positions, transform_positions_into, Bins, Blend,
    Cull, DepthTest, Draw, DrawList, DrawState, RasterScratch, Stats, TileCost,
};
pub use setup::{GUARD_BAND_PX, SUBPIXEL_BITS};

/// Most varyings (floats per vertex) a draw can carry: 24 are the most the lit shader's
/// layout needs (position, normal, five UV channels, colour, tangent), with room to spare.
/// A draw with more is skipped and counted in [`Stats::too_wide`].
pub const MAX_VARYINGS: usize = 32;

/// What the fill loop tells the shader about the triangle being filled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TriInfo {
    /// The `Draw::id` the triangle came from.
    pub draw: u32,
    /// True if the triangle faces the camera (counter-clockwise in normalised device space,
    /// after accounting for `DrawState::flip_winding`).
    pub front: bool,
}

/// Groups of eight lanes a [`Batch`] holds: 64 pixels, whose varyings, derivatives and
/// colours stay in L1 while every stage of a shader runs over them.
pub const GROUPS: usize = 8;

/// Fragments of one draw and facing, as the fill hands them to a shader: up to [`GROUPS`]
/// groups of eight lanes, group `g`'s lane `i` the pixel at offset `o[g] + i` of the tile
/// whose top-left pixel is `(tile_x, tile_y)` (a group is one aligned row of eight pixels of
/// the tile; [`Batch::pixel`]).
#[derive(Clone, Debug)]
pub struct Batch {
    /// The `Draw::id` the fragments came from.
    pub draw: u32,
    /// The fragments' triangles face the camera (counter-clockwise in normalised device
    /// space, after accounting for `DrawState::flip_winding`).
    pub front: bool,
    /// Groups in use: the first `len`.
    pub len: usize,
    /// Floats per vertex of the draw's varyings, and how many of them have derivatives.
    pub stride: usize,
    pub derivatives: usize,
    pub tile_x: u32,
    pub tile_y: u32,
    /// Per group: the tile offset of lane 0 (a multiple of eight; rows are 64 pixels).
    pub o: [u32; GROUPS],
    /// Per group: the live lanes (bit `i` = lane `i`). Other lanes hold finite but
    /// meaningless values. The shader clears the bits of lanes it discards (alpha test).
    pub mask: [u32; GROUPS],
    /// Per group: the draw's varyings, interpolated perspective-correctly at the pixel
    /// centres, one [`F8`] per float of the vertex layout (the first `stride`).
    pub var: [[Lane; MAX_VARYINGS]; GROUPS],
    /// Per group: exact screen-space derivatives, per pixel along +x and +y, of the varyings
    /// in the range [`FragmentShader::derivatives`] asked for (index 0 = the range's first;
    /// the first `derivatives`).
    pub ddx: [[Lane; MAX_VARYINGS]; GROUPS],
    pub ddy: [[Lane; MAX_VARYINGS]; GROUPS],
    /// Per group: the shader's linear-light RGBA.
    pub out: [Colors; GROUPS],
}

impl Default for Batch {
    fn default() -> Self {
        Self {
            draw: 0,
            front: true,
            len: 0,
            stride: 0,
            derivatives: 0,
            tile_x: 0,
            tile_y: 0,
            o: [0; GROUPS],
            mask: [0; GROUPS],
            var: [[Lane::ZERO; MAX_VARYINGS]; GROUPS],
            ddx: [[Lane::ZERO; MAX_VARYINGS]; GROUPS],
            ddy: [[Lane::ZERO; MAX_VARYINGS]; GROUPS],
            out: [Colors::default(); GROUPS],
        }
    }
}

impl Batch {
    /// The pixel of lane 0 of group `g`.
    #[inline(always)]
    #[must_use]
    pub fn pixel(&self, g: usize) -> (u32, u32) {
        let o = self.o[g];
        (self.tile_x + o % TILE, self.tile_y + o / TILE)
    }

    /// The varyings of group `g` (the first `stride`).
    #[inline(always)]
    #[must_use]
    pub fn varyings(&self, g: usize) -> &[Lane] {
        &self.var[g][..self.stride]
    }

    /// Group `g` as eight lanes of fragments.
    #[inline(always)]
    #[must_use]
    pub fn group(&self, g: usize) -> Fragments<'_> {
        Fragments {
            tri: TriInfo {
                draw: self.draw,
                front: self.front,
            },
            mask: self.mask[g],
            var: &self.var[g][..self.stride],
            ddx: &self.ddx[g][..self.derivatives],
            ddy: &self.ddy[g][..self.derivatives],
        }
    }

    /// An empty batch of `draw` and facing `front` in `tile`.
    pub(crate) fn start(
        &mut self,
        tile: &Tile,
        draw: u32,
        front: bool,
        stride: usize,
        derivatives: usize,
    ) {
        self.draw = draw;
        self.front = front;
        self.len = 0;
        self.stride = stride;
        self.derivatives = derivatives;
        self.tile_x = tile.x0;
        self.tile_y = tile.y0;
    }
}

/// One group of a [`Batch`]: eight lanes of fragments of one draw and facing.
#[derive(Clone, Copy, Debug)]
pub struct Fragments<'a> {
    pub tri: TriInfo,
    /// Live lanes: bit `i` = lane `i`.
    pub mask: u32,
    /// The varyings ([`Batch::var`]) and derivatives ([`Batch::ddx`], [`Batch::ddy`]).
    pub var: &'a [Lane],
    pub ddx: &'a [Lane],
    pub ddy: &'a [Lane],
}

/// Linear-light RGBA of eight lanes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Colors {
    pub r: Lane,
    pub g: Lane,
    pub b: Lane,
    pub a: Lane,
}

impl Colors {
    /// The same colour in every lane.
    #[inline(always)]
    #[must_use]
    pub fn splat(c: glam::Vec4) -> Self {
        Self {
            r: Lane::splat(c.x),
            g: Lane::splat(c.y),
            b: Lane::splat(c.z),
            a: Lane::splat(c.w),
        }
    }

    /// Four lanes of level `L`.
    #[inline(always)]
    #[must_use]
    pub fn of<L: Level>(r: F8<L>, g: F8<L>, b: F8<L>, a: F8<L>) -> Self {
        Self {
            r: r.into(),
            g: g.into(),
            b: b.into(),
            a: a.into(),
        }
    }

    /// Lane `i` as a vector.
    #[inline(always)]
    #[must_use]
    pub fn lane(&self, i: usize) -> glam::Vec4 {
        glam::Vec4::new(self.r.0[i], self.g.0[i], self.b.0[i], self.a.0[i])
    }
}

/// The per-fragment half of a shading mode, a [`Batch`] at a time. The fill calls it through
/// `dyn` once per batch: a shader compiles its per-kernel code itself (the stage pipeline of
/// `realist-shade`), so nothing of it is inlined into the fill.
pub trait FragmentShader: Sync {
    /// The varyings `(first, count)` whose screen-space derivatives the shader reads for
    /// triangles of draw `draw` (e.g. a texture's UV, for its level of detail); `None`, the
    /// default, computes none. Asked once per triangle and tile.
    fn derivatives(&self, draw: u32) -> Option<(usize, usize)> {
        let _ = draw;
        None
    }

    /// Whether the fill may defer the fragments of draw `draw` to the end of the tile and
    /// shade only the visible ones (see `fill.rs`, "Deferred shading"): only for a shader
    /// whose colour depends on nothing but the fragment and that never discards a lane of
    /// that draw. Default: false.
    fn defers(&self, draw: u32) -> bool {
        let _ = draw;
        false
    }

    /// Whether the colour of draw `draw`'s fragments is their first three varyings, alpha 1,
    /// with no lane discarded (Gouraud and flat shading: the colour was computed per
    /// vertex or facet). The fill then writes the interpolated varyings itself, at the
    /// depth test, and does not call [`FragmentShader::shade`] for the draw. Default: false.
    fn colour_is_varyings(&self, draw: u32) -> bool {
        let _ = draw;
        false
    }

    /// Whether the shader may discard lanes of draw `draw` (clear bits of [`Batch::mask`]).
    /// A draw that writes no colour and whose shader discards nothing is not shaded at all.
    /// Default: true.
    fn discards(&self, draw: u32) -> bool {
        let _ = draw;
        true
    }

    /// Shades the live lanes of the first `b.len` groups of `b` into `b.out` (linear-light
    /// RGBA) and clears the mask bits of the lanes it discards.
    fn shade(&self, b: &mut Batch);
}

/// A shader written one pixel at a time (tests, tools, simple experiments), run by
/// [`PerPixel`] on each live lane. Slower than a lane shader; no derivatives.
pub trait PixelShader: Sync {
    /// Linear-light RGBA of a fragment with varyings `v`, or `None` to discard it.
    fn pixel(&self, tri: TriInfo, v: &[f32]) -> Option<glam::Vec4>;
}

/// Adapts a [`PixelShader`] to the fill's batches.
pub struct PerPixel<S>(pub S);

impl<S: PixelShader> FragmentShader for PerPixel<S> {
    fn shade(&self, b: &mut Batch) {
        let tri = TriInfo {
            draw: b.draw,
            front: b.front,
        };
        let mut v = [0.0f32; MAX_VARYINGS];
        let n = b.stride.min(MAX_VARYINGS);
        for g in 0..b.len {
            for i in 0..LANES {
                if b.mask[g] >> i & 1 == 0 {
                    continue;
                }
                for (j, x) in v[..n].iter_mut().enumerate() {
                    *x = b.var[g][j].0[i];
                }
                match self.0.pixel(tri, &v[..n]) {
                    Some(c) => {
                        let out = &mut b.out[g];
                        out.r.0[i] = c.x;
                        out.g.0[i] = c.y;
                        out.b.0[i] = c.z;
                        out.a.0[i] = c.w;
                    }
                    None => b.mask[g] &= !(1 << i),
                }
            }
        }
    }
}
