//! The tiled rasterizer: clip-space transform, frustum and back-face culling, near/far and
//! guard-band clipping in homogeneous space, fixed-point triangle setup, binning into 64x64
//! tiles, and per-tile fill with a depth test, run in parallel over tiles.
//!
//! The rasterizer knows no materials, lights or UI. A draw's vertices carry a run-time number
//! of float varyings ([`Draw::stride`], at most [`MAX_VARYINGS`]); set-up stores them per
//! triangle and the fill interpolates them with one loop, eight pixels (one block row) at a
//! time, for a [`FragmentShader`] that shades those eight lanes at once. The fill and the
//! shaders are generic over a [`Kernel`] (portable, AVX2, AVX-512), chosen once at run time
//! ([`kernel`]), so one source gives each instruction set its own inner loops and the
//! per-pixel path has no `dyn`.
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
use realist_simd as simd;

mod clip;
mod fill;
mod framebuffer;
mod line;
mod pipeline;
mod setup;
pub mod stages;

use crate::simd::{Kernel, F8, LANES};

pub use framebuffer::{sample_offsets, DepthCopy, Framebuffer, Target, SAMPLE_COUNTS, TILE};
pub use line::{draw_lines, draw_points, draw_wide_lines, LineStyle, StrokeStyle, MAX_STROKE_PX};
pub use pipeline::{
    draw, draw_list, draw_with_kernel, transform_positions, transform_positions_into, Bins, Blend,
    Cull, DepthTest, Draw, DrawList, DrawState, RasterScratch, Stats, TileCost,
};
pub use setup::{GUARD_BAND_PX, SUBPIXEL_BITS};

/// Most varyings (floats per vertex) a draw can carry: 24 are the most the lit shader's
/// layout needs (position, normal, five UV channels, colour, tangent), with room to spare.
/// A draw with more is skipped and counted in [`Stats::draws_too_wide`].
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

/// One row of up to eight pixels of one triangle, as the fill hands it to a shader: lane
/// `i` is pixel `(x + i, y)`; or, for a shader that [packs](FragmentShader::packs), up to
/// eight pixels anywhere in the tile from triangles of one draw and facing (`x` and `y` are
/// 0 then).
#[derive(Clone, Copy, Debug)]
pub struct Fragments<'a> {
    pub tri: TriInfo,
    pub x: u32,
    pub y: u32,
    /// Live lanes (inside the triangle and passing the depth test): bit `i` = lane `i`.
    /// Other lanes hold finite but meaningless values.
    pub mask: u32,
    /// The draw's varyings, interpolated perspective-correctly at the pixel centres: one
    /// [`F8`] per float of the vertex layout.
    pub var: &'a [F8],
    /// Exact screen-space derivatives, per pixel along +x and +y, of the varyings in the
    /// range [`FragmentShader::derivatives`] asked for (index 0 = the range's first); empty
    /// when none were asked for.
    pub ddx: &'a [F8],
    pub ddy: &'a [F8],
}

/// Linear-light RGBA of eight lanes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Colors {
    pub r: F8,
    pub g: F8,
    pub b: F8,
    pub a: F8,
}

impl Colors {
    /// The same colour in every lane.
    #[inline(always)]
    #[must_use]
    pub fn splat(c: glam::Vec4) -> Self {
        Self {
            r: F8::splat(c.x),
            g: F8::splat(c.y),
            b: F8::splat(c.z),
            a: F8::splat(c.w),
        }
    }

    /// Lane `i` as a vector.
    #[inline(always)]
    #[must_use]
    pub fn lane(&self, i: usize) -> glam::Vec4 {
        glam::Vec4::new(self.r.0[i], self.g.0[i], self.b.0[i], self.a.0[i])
    }
}

/// The per-fragment half of a shading mode, eight pixels at a time.
///
/// `shade` is compiled once per kernel ([`Kernel`]): implementations must mark it
/// `#[inline(always)]` (and what it calls on lanes), so it is compiled inside the kernel's
/// entry point with that kernel's instructions.
pub trait FragmentShader: Sync {
    /// The varyings `(first, count)` whose screen-space derivatives the shader reads for
    /// triangles of draw `draw` (e.g. a texture's UV, for its level of detail); `None`, the
    /// default, computes none. Asked once per triangle and tile.
    #[inline(always)]
    fn derivatives(&self, draw: u32) -> Option<(usize, usize)> {
        let _ = draw;
        None
    }

    /// Whether the fill may defer the fragments of draw `draw` to the end of the tile and
    /// shade only the visible ones, packed into full batches of eight lanes across rows
    /// and triangles (see `fill.rs`, "Deferred shading"): only for a shader whose colour
    /// depends on nothing but the fragment and that never discards a lane of that draw (it
    /// returns `f.mask`). A packed batch's lanes are pixels anywhere in the tile, so `f.x`
    /// and `f.y` do not locate them. Default: false.
    #[inline(always)]
    fn packs(&self, draw: u32) -> bool {
        let _ = draw;
        false
    }

    /// Shades the live lanes of `f` into `out` (linear-light RGBA) and returns the lanes to
    /// write: `f.mask`, or a subset of it to discard some (alpha test).
    fn shade<K: Kernel>(&self, f: &Fragments<'_>, out: &mut Colors) -> u32;
}

/// A shader written one pixel at a time (tests, tools, simple experiments), run by
/// [`PerPixel`] on each live lane. Slower than a lane shader; no derivatives.
pub trait PixelShader: Sync {
    /// Linear-light RGBA of a fragment with varyings `v`, or `None` to discard it.
    fn pixel(&self, tri: TriInfo, v: &[f32]) -> Option<glam::Vec4>;
}

/// Adapts a [`PixelShader`] to the fill's eight-lane interface.
pub struct PerPixel<S>(pub S);

impl<S: PixelShader> FragmentShader for PerPixel<S> {
    #[inline(always)]
    fn shade<K: Kernel>(&self, f: &Fragments<'_>, out: &mut Colors) -> u32 {
        let mut keep = f.mask;
        let mut v = [0.0f32; MAX_VARYINGS];
        let n = f.var.len().min(MAX_VARYINGS);
        for i in 0..LANES {
            if f.mask >> i & 1 == 0 {
                continue;
            }
            for (j, x) in v[..n].iter_mut().enumerate() {
                *x = f.var[j].0[i];
            }
            match self.0.pixel(f.tri, &v[..n]) {
                Some(c) => {
                    out.r.0[i] = c.x;
                    out.g.0[i] = c.y;
                    out.b.0[i] = c.z;
                    out.a.0[i] = c.w;
                }
                None => keep &= !(1 << i),
            }
        }
        keep
    }
}
