//! The tiled rasterizer: clip-space transform, frustum and back-face culling, near/far and
//! guard-band clipping in homogeneous space, fixed-point triangle setup, binning into 64x64
//! tiles, and per-tile fill with a depth test, run in parallel over tiles.
//!
//! The rasterizer knows no materials, lights or UI. It is generic over a
//! [`FragmentShader`] whose associated [`Varying`] type is what gets interpolated, so each
//! shading mode interpolates only what it reads and the per-pixel path has no `dyn`.
//!
//! Phases of one pass ([`draw`]):
//! 1. *setup* (parallel over chunks of triangles, results concatenated in submission order):
//!    trivial frustum reject, clipping where a vertex is outside the near or far plane or the
//!    guard band, perspective divide, snapping to 1/256 pixel, culling, edge equations;
//! 2. *binning* (serial, submission order): each set-up triangle is appended to the bin of
//!    every 64x64 tile its bounding box touches and its edges do not exclude;
//! 3. *fill* (parallel over tiles, each task owns its tile's colour and depth): triangles in
//!    bin order, so 1 and N threads produce bit-identical images.
//!
//! Triangles are processed in batches so memory stays bounded on multi-million-triangle meshes.
//! [`draw_list`] takes the pipeline's working memory ([`Bins`], [`RasterScratch`]) from the
//! caller, so a renderer that keeps it allocates nothing per frame (clipping works on
//! fixed-size polygons on the stack); it also records per-tile cost ([`TileCost`]) and
//! can be stopped between tiles.
//!
//! Rejected designs: a scanline rasterizer (not tile-parallel, fill rule harder to make exact);
//! float edge functions (shared edges can crack or double-cover); binning in parallel with
//! per-thread bins merged later (ordering costs more than the serial append it saves).

mod clip;
mod fill;
mod framebuffer;
mod line;
mod pipeline;
mod setup;
pub mod stages;
mod varying;

pub use framebuffer::{DepthCopy, Framebuffer, Target, TILE};
pub use line::{draw_lines, LineStyle};
pub use pipeline::{
    draw, draw_list, transform_positions, transform_positions_into, Bins, Blend, Cull, DepthTest,
    Draw, DrawList, DrawState, RasterScratch, Stats, TileCost,
};
pub use setup::{GUARD_BAND_PX, SUBPIXEL_BITS};
pub use varying::Varying;

/// What the fill loop tells the shader about the triangle being filled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TriInfo {
    /// The `Draw::id` the triangle came from.
    pub draw: u32,
    /// True if the triangle faces the camera (counter-clockwise in normalised device space,
    /// after accounting for `DrawState::flip_winding`).
    pub front: bool,
}

/// The per-fragment half of a shading mode.
pub trait FragmentShader: Sync {
    /// What is interpolated across the triangle (perspective-correct).
    type Varying: Varying;

    /// Whether the fill loop computes the varying's screen-space derivatives and calls
    /// [`FragmentShader::fragment_grad`] instead of [`FragmentShader::fragment`]. A
    /// compile-time constant, so shaders that leave it `false` pay nothing.
    const DERIVATIVES: bool = false;

    /// Linear-light RGBA of a fragment, or `None` to discard it (alpha test).
    fn fragment(&self, tri: TriInfo, v: &Self::Varying) -> Option<glam::Vec4>;

    /// [`FragmentShader::fragment`] with the exact derivatives of the perspective-correct
    /// varying at the pixel centre, per pixel along +x (right) and +y (down); called
    /// instead of `fragment` when [`FragmentShader::DERIVATIVES`] is true. The default
    /// ignores them.
    #[inline(always)]
    fn fragment_grad(
        &self,
        tri: TriInfo,
        v: &Self::Varying,
        dvdx: &Self::Varying,
        dvdy: &Self::Varying,
    ) -> Option<glam::Vec4> {
        let _ = (dvdx, dvdy);
        self.fragment(tri, v)
    }
}
