//! One raster pass: transform, cull, clip, set up, bin, fill (see the module docs of
//! [`crate::raster`] for the phases).

use std::time::Instant;

use glam::{Mat4, Vec2, Vec3, Vec4};
use rayon::prelude::*;

use super::clip::{clip_polygon, outcode, ClipVertex, Poly};
use super::fill::{fill, FillCounters};
use super::framebuffer::{Target, TILE};
use super::setup::{setup, Reject, SetupTri, GUARD_BAND_PX};
use super::FragmentShader;

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
        }
    }
}

/// A batch of triangles sharing state, with clip-space positions and varyings per vertex.
#[derive(Clone, Copy, Debug)]
pub struct Draw<'a, V> {
    /// Passed to the shader in [`super::TriInfo::draw`].
    pub id: u32,
    pub clip: &'a [Vec4],
    pub varyings: &'a [V],
    /// Vertex indices; triangles with an index out of range are dropped as degenerate.
    pub triangles: &'a [[u32; 3]],
    pub state: DrawState,
}

/// Counters of what the pipeline did and skipped (`--stats`).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Stats {
    pub triangles_in: u64,
    /// Whole objects skipped by their bounding sphere (counted by the caller).
    pub objects_culled: u64,
    /// Triangles inside culled objects or entirely outside one frustum plane.
    pub culled_frustum: u64,
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
    pub depth_rejected: u64,
    pub lines_drawn: u64,
}

impl Stats {
    /// Adds another pass's counters.
    pub fn add(&mut self, o: &Stats) {
        self.triangles_in += o.triangles_in;
        self.objects_culled += o.objects_culled;
        self.culled_frustum += o.culled_frustum;
        self.culled_backface += o.culled_backface;
        self.culled_degenerate += o.culled_degenerate;
        self.clipped += o.clipped;
        self.drawn += o.drawn;
        self.tiles += o.tiles;
        self.pixels_shaded += o.pixels_shaded;
        self.depth_rejected += o.depth_rejected;
        self.lines_drawn += o.lines_drawn;
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

/// Triangles set up per parallel chunk.
const CHUNK: usize = 2048;
/// Set-up triangles held before the tiles are filled (bounds memory on huge meshes).
const BATCH: usize = 64 * 1024;

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
pub trait DrawList<V>: Sync {
    /// Number of draws.
    fn count(&self) -> usize;
    /// Draw `i`, for `i < count()`.
    fn draw(&self, i: usize) -> Draw<'_, V>;
}

impl<V: Sync> DrawList<V> for [Draw<'_, V>] {
    fn count(&self) -> usize {
        self.len()
    }
    fn draw(&self, i: usize) -> Draw<'_, V> {
        let d = &self[i];
        Draw {
            id: d.id,
            clip: d.clip,
            varyings: d.varyings,
            triangles: d.triangles,
            state: d.state,
        }
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

/// Per-tile memory of the pipeline that does not depend on the varying type: the bins and
/// the per-tile costs. Kept between passes and frames; the lists of the largest tile count
/// seen are kept, so switching between sizes allocates nothing.
#[derive(Debug, Default)]
pub struct Bins {
    bins: Vec<Vec<u32>>,
    costs: Vec<TileCost>,
    /// Tiles of the current target (the first `active` entries are in use).
    active: usize,
    /// Wall-clock nanoseconds in clip / cull / setup / binning, and in filling, summed over
    /// the passes since the last [`Bins::reset_costs`].
    pub setup_nanos: u64,
    pub fill_nanos: u64,
}

impl Bins {
    /// Total entries over all tiles.
    pub(crate) fn entries(&self) -> usize {
        self.bins[..self.active].iter().map(Vec::len).sum()
    }

    /// The per-tile triangle lists.
    pub(crate) fn lists(&mut self) -> &mut [Vec<u32>] {
        &mut self.bins[..self.active]
    }

    /// Uses `tiles` tiles (allocates only beyond the largest count seen).
    pub(crate) fn fit(&mut self, tiles: usize) {
        if self.bins.len() < tiles {
            self.bins.resize_with(tiles, Vec::new);
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

/// Memory of the pipeline that depends on the varying type (set-up triangles), kept
/// between passes and frames.
#[derive(Debug)]
pub struct RasterScratch<V> {
    pending: Vec<SetupTri<V>>,
    chunks: Vec<(Vec<SetupTri<V>>, Stats)>,
}

impl<V> Default for RasterScratch<V> {
    fn default() -> Self {
        Self {
            pending: Vec::new(),
            chunks: Vec::new(),
        }
    }
}

/// Rasterizes `draws` in order into `target` with `shader`. Runs on the current rayon pool;
/// the image does not depend on its thread count. Allocates its working memory; a caller
/// that draws every frame uses [`draw_list`] with memory it keeps.
pub fn draw<S: FragmentShader>(
    target: &mut Target,
    draws: &[Draw<'_, S::Varying>],
    shader: &S,
    stats: &mut Stats,
) {
    let mut bins = Bins::default();
    let mut scratch = RasterScratch::default();
    draw_list(
        target,
        draws,
        shader,
        stats,
        &mut bins,
        &mut scratch,
        &|| false,
    );
}

/// [`draw`] with kept memory and a stop signal: `stop` is asked before each tile is filled,
/// and once it answers true the remaining tiles of the pass are skipped and `false` is
/// returned (the target then holds a partial image). Returns `true` if the pass completed.
/// Allocates nothing once `bins` and `scratch` have served a pass of this size.
pub fn draw_list<S: FragmentShader, L: DrawList<S::Varying> + ?Sized>(
    target: &mut Target,
    draws: &L,
    shader: &S,
    stats: &mut Stats,
    bins: &mut Bins,
    scratch: &mut RasterScratch<S::Varying>,
    stop: &(dyn Fn() -> bool + Sync),
) -> bool {
    let g = guard(target.width, target.height);
    let (w, h) = (target.width, target.height);
    bins.fit(target.tiles.len());
    let RasterScratch { pending, chunks } = scratch;
    pending.clear();
    let mut complete = true;
    let start = Instant::now();
    let fill_before = bins.fill_nanos;
    for i in 0..draws.count() {
        let d = draws.draw(i);
        stats.triangles_in += d.triangles.len() as u64;
        for batch in d.triangles.chunks(BATCH) {
            let n = batch.len().div_ceil(CHUNK);
            if chunks.len() < n {
                chunks.resize_with(n, || (Vec::new(), Stats::default()));
            }
            chunks[..n]
                .par_iter_mut()
                .zip(batch.par_chunks(CHUNK))
                .for_each(|((out, st), tris)| {
                    out.clear();
                    *st = Stats::default();
                    for t in tris {
                        assemble(&d, t, g, w, h, out, st);
                    }
                });
            for (tris, st) in &chunks[..n] {
                stats.add(st);
                for t in tris {
                    if pending.len() >= BATCH {
                        complete &= flush(target, pending, bins, shader, stats, stop);
                    }
                    bin(target, t, pending.len() as u32, bins.lists());
                    pending.push(*t);
                }
            }
        }
    }
    complete &= flush(target, pending, bins, shader, stats, stop);
    let total = start.elapsed().as_nanos() as u64;
    bins.setup_nanos += total.saturating_sub(bins.fill_nanos - fill_before);
    complete
}

/// Culls, clips and sets up one input triangle, appending the results to `out`.
pub(crate) fn assemble<V: super::Varying>(
    d: &Draw<'_, V>,
    t: &[u32; 3],
    g: Vec2,
    w: u32,
    h: u32,
    out: &mut Vec<SetupTri<V>>,
    st: &mut Stats,
) {
    let fetch = |i: u32| -> Option<ClipVertex<V>> {
        let (p, v) = (d.clip.get(i as usize)?, d.varyings.get(i as usize)?);
        p.is_finite().then_some(ClipVertex { pos: *p, var: *v })
    };
    let (Some(a), Some(b), Some(c)) = (fetch(t[0]), fetch(t[1]), fetch(t[2])) else {
        st.culled_degenerate += 1;
        return;
    };
    // Trivial reject against the real frustum; clipping needs against near/far and guard band.
    let (fa, fb, fc) = (
        outcode(a.pos, Vec2::ONE),
        outcode(b.pos, Vec2::ONE),
        outcode(c.pos, Vec2::ONE),
    );
    if fa & fb & fc != 0 {
        st.culled_frustum += 1;
        return;
    }
    let (ga, gb, gc) = (outcode(a.pos, g), outcode(b.pos, g), outcode(c.pos, g));
    let need = ga | gb | gc;
    let mut ccw = None;
    let mut push = |tri: [&ClipVertex<V>; 3], ccw: Option<bool>, st: &mut Stats| match setup(
        tri, w, h, d.id, d.state, ccw,
    ) {
        Ok(s) => {
            out.push(s);
            true
        }
        Err(Reject::Backface) => {
            st.culled_backface += 1;
            false
        }
        Err(Reject::Degenerate) => {
            st.culled_degenerate += 1;
            false
        }
    };
    if need == 0 {
        let _ = push([&a, &b, &c], ccw, st);
        return;
    }
    st.clipped += 1;
    // The orientation every piece must keep: the sign of det[X; Y; W] of the whole triangle
    // (homogeneous rasterization: positive = counter-clockwise in NDC where w > 0).
    let det = homogeneous_orientation(a.pos, b.pos, c.pos);
    if det == 0.0 || !det.is_finite() {
        st.culled_degenerate += 1;
        return;
    }
    ccw = Some(det > 0.0);
    // Clip against every violated plane (near first: it guarantees w > 0 afterwards).
    let poly = clip_polygon(Poly::triangle([a, b, c]), need, g);
    let poly = poly.as_slice();
    if poly.len() < 3 {
        st.culled_frustum += 1;
        return;
    }
    let mut rejected = Stats::default();
    let mut any = false;
    for i in 1..poly.len() - 1 {
        any |= push([&poly[0], &poly[i], &poly[i + 1]], ccw, &mut rejected);
    }
    // Count the input triangle once: as drawn if any piece survived, else by the first reason.
    if !any {
        if rejected.culled_backface > 0 {
            st.culled_backface += 1;
        } else {
            st.culled_degenerate += 1;
        }
    }
}

/// det[X; Y; W] of a clip-space triangle, in f64: its sign is the orientation of the
/// triangle's visible (w > 0) part in NDC, positive for counter-clockwise.
fn homogeneous_orientation(a: Vec4, b: Vec4, c: Vec4) -> f64 {
    let [a, b, c] = [a, b, c].map(|p| [f64::from(p.x), f64::from(p.y), f64::from(p.w)]);
    a[0] * (b[1] * c[2] - c[1] * b[2]) - b[0] * (a[1] * c[2] - c[1] * a[2])
        + c[0] * (a[1] * b[2] - b[1] * a[2])
}

/// Appends triangle `index` to the bin of every tile its bounds touch and its edges do not
/// exclude (a tile is excluded when one edge is negative at all four of its corners).
pub(crate) fn bin<V>(target: &Target, t: &SetupTri<V>, index: u32, bins: &mut [Vec<u32>]) {
    let (tx0, ty0, tx1, ty1) = (t.x0 / TILE, t.y0 / TILE, t.x1 / TILE, t.y1 / TILE);
    let single = tx0 == tx1 && ty0 == ty1;
    for ty in ty0..=ty1 {
        for tx in tx0..=tx1 {
            if !single && tile_outside(t, tx * TILE, ty * TILE) {
                continue;
            }
            bins[(ty * target.tiles_x + tx) as usize].push(index);
        }
    }
}

fn tile_outside<V>(t: &SetupTri<V>, x: u32, y: u32) -> bool {
    use super::setup::ONE;
    let (px, py) = (i64::from(x) * ONE + ONE / 2, i64::from(y) * ONE + ONE / 2);
    let span = i64::from(TILE - 1) * ONE;
    (0..3).any(|k| {
        let e = t.a[k] * px + t.b[k] * py + t.c[k] + t.bias[k];
        e + (t.a[k] * span).max(0) + (t.b[k] * span).max(0) < 0
    })
}

/// Fills every tile with its binned triangles (in parallel over tiles), then empties the bins
/// and `pending`. Tiles are skipped once `stop` answers true; returns false if any was.
pub(crate) fn flush<S: FragmentShader>(
    target: &mut Target,
    pending: &mut Vec<SetupTri<S::Varying>>,
    bins: &mut Bins,
    shader: &S,
    stats: &mut Stats,
    stop: &(dyn Fn() -> bool + Sync),
) -> bool {
    if pending.is_empty() {
        return true;
    }
    stats.drawn += pending.len() as u64;
    let tris = &*pending;
    let start = Instant::now();
    let (tiles, shaded, rejected, skipped) = target
        .tiles
        .par_iter_mut()
        .zip(bins.bins[..bins.active].par_iter_mut())
        .zip(bins.costs[..bins.active].par_iter_mut())
        .filter(|((_, b), _)| !b.is_empty())
        .map(|((tile, bin), cost)| {
            if stop() {
                bin.clear();
                return (0, 0, 0, 1);
            }
            let start = Instant::now();
            let mut n = FillCounters::default();
            tile.materialize();
            for &i in bin.iter() {
                fill(tile, &tris[i as usize], shader, &mut n);
            }
            bin.clear();
            cost.nanos += start.elapsed().as_nanos() as u64;
            cost.fragments += n.shaded;
            (1, n.shaded, n.depth_rejected, 0)
        })
        .reduce(
            || (0, 0, 0, 0),
            |a, b| (a.0 + b.0, a.1 + b.1, a.2 + b.2, a.3 + b.3),
        );
    stats.tiles += tiles;
    stats.pixels_shaded += shaded;
    stats.depth_rejected += rejected;
    pending.clear();
    bins.fill_nanos += start.elapsed().as_nanos() as u64;
    skipped == 0
}
