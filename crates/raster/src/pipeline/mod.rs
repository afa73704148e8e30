//! One raster pass: transform, cull, clip, set up, bin, fill (see the module docs of
//! [`crate`] for the phases).

use std::cell::RefCell;
use std::time::Instant;

use glam::{Mat4, Vec2, Vec3, Vec4};
use rayon::prelude::*;

use super::clip::{
    clip_polygon, clip_sections, outcode, section_code, ClipVertex, Poly, MAX_SECTIONS,
};
use super::fill::{FillFns, FillScratch};
use super::framebuffer::{Target, TILE};
use super::setup::{
    project, project3, setup_projected, Corners, Reject, ScreenVert, SetupTri, Viewport,
    GUARD_BAND_PX,
};
use super::{FragmentShader, MAX_VARYINGS};
use crate::simd::kernel::{KernelJob, KernelKind};
use crate::simd::Level;

mod pass;
mod primitive;
pub use pass::{draw, draw_list, draw_with_kernel};
pub(crate) use primitive::*;

/// Which faces are discarded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Cull {
    None,
    #[default]
    Back,
    Front,
}

/// How a fragment's colour combines with the target.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Blend {
    #[default]
    Replace,
    /// Source over destination with the fragment's alpha (straight alpha).
    Alpha,
    /// Component-wise sum (used by coverage counting).
    Add,
}

/// Depth comparison (reversed-Z: larger is nearer).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum DepthTest {
    #[default]
    Greater,
    GreaterEqual,
    Always,
}

/// Fixed-function state of a draw. The default is [`DrawState::opaque`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawState {
    pub cull: Cull,
    pub depth_test: DepthTest,
    pub depth_write: bool,
    pub blend: Blend,
    /// Write colour (false for depth-only passes).
    pub color_write: bool,
    /// Treat clockwise triangles as front-facing (a mirroring model matrix, det < 0).
    pub flip_winding: bool,
    /// Slope-scaled depth offset (as `glPolygonOffset(factor, 0)`): depth is moved away from
    /// the eye by this many times the triangle's largest depth change per pixel. Used so
    /// lines drawn on a surface win against the surface itself.
    pub depth_offset: f32,
    /// Sub-pixel bits of the vertex snap, 0..=[`super::SUBPIXEL_BITS`] (larger values are
    /// treated as the maximum). Fewer bits emulate a coarser fixed-point rasterizer exactly,
    /// for accuracy sweeps; the edge functions keep their precision.
    pub subpixel_bits: u8,
    /// The vertices' varyings are two halves, for front-facing then back-facing triangles
    /// (e.g. Gouraud colours lit from both sides): set-up keeps only the half for each
    /// triangle's facing, so the fill interpolates half as much.
    pub facing_varyings: bool,
}

impl Default for DrawState {
    fn default() -> Self {
        Self::opaque()
    }
}

impl DrawState {
    /// Opaque geometry: back faces culled, depth tested and written, colour replaced.
    #[must_use]
    pub fn opaque() -> Self {
        Self {
            cull: Cull::Back,
            depth_test: DepthTest::Greater,
            depth_write: true,
            blend: Blend::Replace,
            color_write: true,
            flip_winding: false,
            depth_offset: 0.0,
            subpixel_bits: super::SUBPIXEL_BITS as u8,
            facing_varyings: false,
        }
    }
}

/// A batch of triangles sharing state, with clip-space positions and `stride` float
/// varyings per vertex.
#[derive(Clone, Copy, Debug)]
pub struct Draw<'a> {
    /// Passed to the shader in [`super::TriInfo::draw`].
    pub id: u32,
    pub clip: &'a [Vec4],
    /// Vertex `i`'s varyings are `varyings[i * stride..(i + 1) * stride]`.
    pub varyings: &'a [f32],
    /// Floats per vertex, at most [`MAX_VARYINGS`] (a draw with more is skipped, its
    /// triangles counted in [`Stats::too_wide`]).
    pub stride: usize,
    /// Vertex indices; triangles with an index out of range are dropped as degenerate.
    pub triangles: &'a [[u32; 3]],
    pub state: DrawState,
    /// Section planes in clip space (at most [`MAX_SECTIONS`](crate::MAX_SECTIONS); more
    /// are ignored): what lies where `dot(plane, clip position) < 0` is cut away, the
    /// triangles crossing a plane clipped like those crossing the near plane. Usually empty.
    pub sections: &'a [Vec4],
}

/// Counters of what the pipeline did and skipped (`--stats`).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Stats {
    pub triangles_in: u64,
    /// Whole objects skipped by their bounding sphere (counted by the caller).
    pub objects_culled: u64,
    /// Triangles inside culled objects or entirely outside one frustum plane.
    pub culled_frustum: u64,
    /// Triangles entirely on the removed side of a section plane.
    pub culled_section: u64,
    pub culled_backface: u64,
    /// Zero area after snapping, non-finite coordinates, bad indices, or no pixel centre.
    pub culled_degenerate: u64,
    /// Triangles that needed clipping (near/far plane or guard band).
    pub clipped: u64,
    /// Set-up triangles binned (a clipped triangle can yield several).
    pub drawn: u64,
    /// Non-empty tile bins filled.
    pub tiles: u64,
    pub pixels_shaded: u64,
    /// Shader calls (eight-lane block rows with at least one live pixel): the lanes in use
    /// are `pixels_shaded / (8 * shader_calls)`.
    pub shader_calls: u64,
    pub depth_rejected: u64,
    pub lines_drawn: u64,
    /// Points of meshes drawn (at least one pixel passed).
    pub points_drawn: u64,
    /// (object, light) pairs skipped because the light cannot reach the object (out of
    /// range, or its cone misses the bounding sphere); counted by the caller.
    pub lights_skipped: u64,
    /// Triangles of draws with more than [`MAX_VARYINGS`] floats per vertex, not drawn
    /// (no shader of this crate asks for that many; a custom one might).
    pub too_wide: u64,
    /// Shadow maps rendered (counted by the caller).
    pub shadow_maps: u64,
}

impl Stats {
    /// Adds another pass's counters.
    pub fn add(&mut self, o: &Stats) {
        self.triangles_in += o.triangles_in;
        self.objects_culled += o.objects_culled;
        self.culled_frustum += o.culled_frustum;
        self.culled_section += o.culled_section;
        self.culled_backface += o.culled_backface;
        self.culled_degenerate += o.culled_degenerate;
        self.clipped += o.clipped;
        self.drawn += o.drawn;
        self.tiles += o.tiles;
        self.pixels_shaded += o.pixels_shaded;
        self.shader_calls += o.shader_calls;
        self.depth_rejected += o.depth_rejected;
        self.lines_drawn += o.lines_drawn;
        self.points_drawn += o.points_drawn;
        self.lights_skipped += o.lights_skipped;
        self.too_wide += o.too_wide;
        self.shadow_maps += o.shadow_maps;
    }
}

/// Model-view-projection transform of positions, in parallel.
#[must_use]
pub fn transform_positions(mvp: Mat4, positions: &[Vec3]) -> Vec<Vec4> {
    let mut out = Vec::new();
    transform_positions_into(mvp, positions, &mut out);
    out
}

/// [`transform_positions`] appended to `out` (in parallel; no allocation when `out` has the
/// capacity).
pub fn transform_positions_into(mvp: Mat4, positions: &[Vec3], out: &mut Vec<Vec4>) {
    out.par_extend(
        positions
            .par_iter()
            .with_min_len(4096)
            .map(|p| mvp * p.extend(1.0)),
    );
}

/// Input triangles set up per parallel chunk (its pieces after clipping stay below 65536,
/// so a tile list holds u16 indices).
pub(crate) const CHUNK: usize = 2048;
/// Input triangles set up before the tiles are filled (bounds memory on huge meshes).
const BATCH: usize = 8 * CHUNK;

/// Guard-band scale of the x/y clip planes for a target size.
pub(crate) fn guard(width: u32, height: u32) -> Vec2 {
    Vec2::new(
        1.0 + 2.0 * GUARD_BAND_PX / width as f32,
        1.0 + 2.0 * GUARD_BAND_PX / height as f32,
    )
}

/// Draws read one at a time by [`draw_list`]: a slice of [`Draw`]s, or a renderer's own
/// per-frame list that builds each draw from plain indices (so the list itself can live in
/// memory kept from frame to frame).
pub trait DrawList: Sync {
    /// Number of draws.
    fn count(&self) -> usize;
    /// Draw `i`, for `i < count()`.
    fn draw(&self, i: usize) -> Draw<'_>;
}

impl DrawList for [Draw<'_>] {
    fn count(&self) -> usize {
        self.len()
    }
    fn draw(&self, i: usize) -> Draw<'_> {
        self[i]
    }
}

/// Cost of one tile in a frame, for the per-tile heat map: summed over the passes since the
/// last [`Bins::reset_costs`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TileCost {
    /// Wall-clock nanoseconds spent filling the tile (by whichever thread filled it).
    pub nanos: u64,
    /// Fragments shaded in the tile.
    pub fragments: u64,
}

/// Per-tile state of the pipeline kept between passes and frames: the per-tile costs, the
/// stage times and the kernel the fill runs with.
#[derive(Debug)]
pub struct Bins {
    costs: Vec<TileCost>,
    /// Tiles of the current target (the first `active` entries are in use).
    active: usize,
    /// Wall-clock nanoseconds in clip / cull / setup / binning, and in filling, summed over
    /// the passes since the last [`Bins::reset_costs`].
    pub setup_nanos: u64,
    pub fill_nanos: u64,
    /// The kernel the fill and shaders run with ([`KernelKind::best`] by default; one the CPU
    /// lacks runs as the portable kernel).
    pub kernel: KernelKind,
}

impl Default for Bins {
    fn default() -> Self {
        Self {
            costs: Vec::new(),
            active: 0,
            setup_nanos: 0,
            fill_nanos: 0,
            kernel: KernelKind::best(),
        }
    }
}

impl Bins {
    /// Pipeline state whose fill runs with `kernel`.
    #[must_use]
    pub fn with_kernel(kernel: KernelKind) -> Self {
        Self {
            kernel,
            ..Self::default()
        }
    }

    /// Uses `tiles` tiles (allocates only beyond the largest count seen).
    pub(crate) fn fit(&mut self, tiles: usize) {
        if self.costs.len() < tiles {
            self.costs.resize(tiles, TileCost::default());
        }
        if self.active != tiles {
            self.costs[..tiles].fill(TileCost::default());
        }
        self.active = tiles;
    }

    /// Zeroes the per-tile costs and the stage times (at the start of a frame).
    pub fn reset_costs(&mut self) {
        self.costs.fill(TileCost::default());
        self.setup_nanos = 0;
        self.fill_nanos = 0;
    }

    /// Costs per tile of the last target drawn, in the order of [`Target::tiles`].
    #[must_use]
    pub fn costs(&self) -> &[TileCost] {
        &self.costs[..self.active]
    }
}

/// The set-up triangles of one chunk of input triangles, their varyings, and per tile the
/// indices of those that touch it.
#[derive(Debug, Default)]
pub(crate) struct Chunk {
    pub tris: Vec<SetupTri>,
    pub attrs: Vec<f32>,
    /// Per tile of the target, indices into `tris`, in order.
    pub bins: Vec<Vec<u16>>,
    pub stats: Stats,
}

impl Chunk {
    /// Empties the chunk for a target of `tiles` tiles, keeping its memory.
    pub fn reset(&mut self, tiles: usize) {
        self.tris.clear();
        self.attrs.clear();
        if self.bins.len() < tiles {
            self.bins.resize_with(tiles, Vec::new);
        }
        for b in &mut self.bins[..tiles] {
            b.clear();
        }
        self.stats = Stats::default();
    }
}

/// Working memory of the pipeline (set-up triangles and tile lists per chunk), kept between
/// passes and frames.
#[derive(Debug, Default)]
pub struct RasterScratch {
    chunks: Vec<Chunk>,
    /// First global triangle index of each draw.
    starts: Vec<usize>,
    /// Every draw's vertices projected once (first vertex of draw `i` at `pre_starts[i]`).
    pre: Vec<PreVert>,
    pre_starts: Vec<usize>,
}

/// A vertex as triangle set-up needs it, computed once per vertex rather than once per
/// triangle using it: its outcodes against the frustum and the guard band, and (if it is
/// inside the guard band) its projected, snapped position.
///
/// Stored in 20 bytes (one per vertex of every draw, held for the frame: 100 MB at 10
/// million triangles): the snapped position in `i32`, which holds every snapped coordinate
/// (at most 2^23 in magnitude, see `setup::snap`); [`PreVert::screen`] widens it.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct PreVert {
    x: i32,
    y: i32,
    z: f32,
    iw: f32,
    frustum: u8,
    guard: u8,
    /// `s` is valid (inside the guard band and w > 0).
    projected: bool,
}

impl PreVert {
    /// The snapped screen position, depth and 1/w.
    #[inline(always)]
    fn screen(self) -> ScreenVert {
        ScreenVert {
            x: i64::from(self.x),
            y: i64::from(self.y),
            z: self.z,
            iw: self.iw,
        }
    }

    #[inline(always)]
    fn new(p: Vec4, g: Vec2, hw: f32, hh: f32, bits: u8) -> Self {
        if !p.is_finite() {
            return Self::default();
        }
        let guard = outcode(p, g);
        let s = if guard == 0 {
            project(p, hw, hh, bits)
        } else {
            None
        };
        let projected = s.is_some();
        let s = s.unwrap_or_default();
        Self {
            // `snap` clamps to ±2^23: lossless.
            x: s.x as i32,
            y: s.y as i32,
            z: s.z,
            iw: s.iw,
            frustum: outcode(p, Vec2::ONE),
            guard,
            projected,
        }
    }
}

/// Projects a run of vertices, compiled per kernel (the snap's rounding is one
/// instruction in the kernels that have it).
struct ProjectJob<'a> {
    clip: &'a [Vec4],
    out: &'a mut [PreVert],
    g: Vec2,
    half: (f32, f32),
    bits: u8,
}

impl KernelJob for ProjectJob<'_> {
    type Output = ();
    #[inline(always)]
    fn run<L: Level>(self) {
        let (hw, hh) = self.half;
        for (o, p) in self.out.iter_mut().zip(self.clip) {
            *o = PreVert::new(*p, self.g, hw, hh, self.bits);
        }
    }
}

/// Vertices projected per parallel task.
const PROJECT_CHUNK: usize = 4096;

/// The set-up of one chunk, compiled per kernel (rounding, conversions and divisions of
/// the fixed-point set-up become single instructions where the kernel has them).
struct SetupJob<'a, L: ?Sized> {
    draws: &'a L,
    starts: &'a [usize],
    pre: &'a [PreVert],
    pre_starts: &'a [usize],
    lo: usize,
    hi: usize,
    g: Vec2,
    vp: Viewport,
    tiles_x: u32,
    chunk: &'a mut Chunk,
}

impl<D: DrawList + ?Sized> KernelJob for SetupJob<'_, D> {
    type Output = ();
    #[inline(always)]
    fn run<L: Level>(self) {
        setup_range(
            self.draws,
            self.starts,
            self.pre,
            self.pre_starts,
            self.lo,
            self.hi,
            self.g,
            self.vp,
            self.tiles_x,
            self.chunk,
        );
    }
}

/// Sets up and bins the global triangles `lo..hi` into `chunk`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn setup_range<L: DrawList + ?Sized>(
    draws: &L,
    starts: &[usize],
    pre: &[PreVert],
    pre_starts: &[usize],
    lo: usize,
    hi: usize,
    g: Vec2,
    vp: Viewport,
    tiles_x: u32,
    chunk: &mut Chunk,
) {
    // The draw holding triangle `lo` (the last draw starting at or before it).
    let mut di = starts.partition_point(|&s| s <= lo).saturating_sub(1);
    let mut at = lo;
    while at < hi && di < starts.len() {
        let d = draws.draw(di);
        let first = at - starts[di];
        let take = (d.triangles.len().saturating_sub(first)).min(hi - at);
        if d.stride > MAX_VARYINGS {
            // Reported, not silently dropped: `Stats::too_wide` (stats, `--stats`).
            chunk.stats.too_wide += take as u64;
        } else {
            let verts = pre.get(pre_starts[di]..pre_starts[di] + d.clip.len());
            for t in &d.triangles[first..first + take] {
                assemble(&d, verts, t, g, vp, Some(tiles_x), chunk);
            }
        }
        at += take;
        di += 1;
    }
    chunk.stats.drawn += chunk.tris.len() as u64;
}
