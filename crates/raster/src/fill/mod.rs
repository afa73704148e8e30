//! Per-tile fill: coverage, depth, a visibility buffer, and batches of fragments for the
//! shader.
//!
//! - Sample positions: pixel centres, (x + 0.5, y + 0.5) in pixels, i.e. `x * 256 + 128` in
//!   fixed point ([`SUBPIXEL_BITS`](super::SUBPIXEL_BITS) = 8 sub-pixel bits). A
//!   multisampled tile ([`Tile::samples`] = 4) adds the offsets of
//!   [`sample_offsets`](super::framebuffer::sample_offsets) (multiples of 1/16 pixel, so
//!   exact in fixed point): coverage and depth are tested at each sample, the shader runs
//!   once per pixel and triangle at the pixel centre (its barycentrics clamped to the
//!   triangle where the centre lies outside, so the attributes are those of the nearest
//!   point of the triangle along the clamping), and its colour is written to the samples
//!   that passed.
//! - Fill rule: top-left (see `setup`), so a pixel on an edge shared by two triangles is
//!   filled by exactly one of them.
//! - The tile is walked in 8x8 blocks. A block is skipped when one edge is negative at all
//!   its sample points, and filled without edge tests when all three edges are non-negative
//!   at all of them (edge functions are linear, so the extremes lie at block corners).
//!   Each row of a block is one eight-lane step: a coverage mask from the exact integer
//!   edge values, then the depth test.
//! - Deferred shading (every opaque draw of a shader that [defers](FragmentShader::defers)
//!   it, on a single-sample tile with colour replaced): the fill only tests coverage and
//!   depth, writes each passing fragment's depth, and keeps per pixel the triangle of the
//!   last fragment that passed (a visibility buffer of one `u32` a pixel: with the depth,
//!   32 KB a tile, in L1). At the end of the tile, or before a triangle that is not deferred
//!   (it may blend with what is under it), the visible pixels are shaded: each row of eight
//!   pixels ("group") of the tile with a live lane, triangle by triangle within the group,
//!   its barycentrics recomputed from the triangle's exact integer edge values at the
//!   group's pixels, its varyings interpolated into the lanes of that triangle. Groups of
//!   one draw and facing are gathered into [`Batch`]es of up to [`GROUPS`] groups and
//!   shaded together. Each pixel is shaded once, by the triangle that drawing in order would
//!   have left there, with the same interpolation, so images are bit for bit those of
//!   shading every fragment in order (a test checks it).
//! - Direct colour (a draw whose colour is its interpolated varyings: Gouraud and flat, see
//!   [`FragmentShader::colour_is_varyings`]): the fill writes the colour at the depth test,
//!   with the same interpolation, and calls no shader.
//! - Forward shading (blending, alpha-tested draws, multisampled tiles): the rows of one
//!   triangle that passed the depth test are gathered into a batch (one triangle at a time:
//!   a later triangle must test against the depth this one writes), shaded, and written
//!   with the draw's blend; depth is written for the lanes the shader kept. A depth-only
//!   draw whose shader discards nothing is not shaded at all: its depth is written at the
//!   test.
//! - Depth: early test before shading, reversed-Z, `z` interpolated linearly in screen space
//!   (z/w is affine there). Attributes are interpolated perspective-correctly:
//!   `p_k = λ_k (1/w_k) / Σ λ_j (1/w_j)` with screen-space barycentrics `λ_k = E_k / area`,
//!   then `V = V_0 + p_1 (V_1 - V_0) + p_2 (V_2 - V_0)`.
//! - Derivatives (of the varyings [`FragmentShader::derivatives`] names): exact, analytic, at the pixel
//!   centre, not differences over 2x2 quads. The `λ_k` are affine in screen space with
//!   per-pixel steps `∂λ_k/∂x = a_k ONE / area`, `∂λ_k/∂y = b_k ONE / area`; with
//!   `D = Σ λ_j (1/w_j)` (so `∂D/∂x = Σ ∂λ_j/∂x (1/w_j)`, constant over the triangle),
//!   `∂p_k/∂x = (1/w_k)(∂λ_k/∂x D - λ_k ∂D/∂x) / D² = (∂λ_k/∂x (1/w_k) - p_k ∂D/∂x) / D`,
//!   and `∂V/∂x = ∂p_1/∂x (V_1 - V_0) + ∂p_2/∂x (V_2 - V_0)`; likewise for y. A piece of a
//!   clipped triangle carries its own vertices' 1/w and varyings (interpolated in clip
//!   space), so this is the derivative of the original triangle's varying there too.
//!
//! The fill of a tile is a few functions per kernel (through
//! [`per_kernel!`](crate::simd::per_kernel)): the loop over its triangles
//! ([`fill_tile_k`]), the visibility pass, the direct and forward fills, the resolve and
//! the interpolation, each called through a pointer picked once per tile; the shader is
//! called through `dyn` once per batch, so no shading code is compiled into them.

// Lane and edge loops index several arrays by one counter on purpose: that shape vectorises.
#![allow(clippy::needless_range_loop)]

use super::framebuffer::{sample_offsets, sample_reach, Tile, TILE, TILE_PIXELS};
use super::pipeline::{Blend, Chunk, DepthTest, DrawState};
use super::setup::{padded, SetupTri, ONE};
use super::{Batch, Colors, FragmentShader, GROUPS, MAX_VARYINGS};
use crate::simd::kernel::{edge_signs, prefetch};
use crate::simd::{mad, Lane, Level, F8, I8, LANES, M8};

mod blocks;
use blocks::*;
mod shading;
use shading::*;

const BLOCK: u32 = 8;
const HALF: i64 = ONE / 2;
/// Samples per pixel of a multisampled tile.
const SAMPLES: usize = 4;
/// Groups of eight pixels in a tile.
const TILE_GROUPS: usize = TILE_PIXELS / LANES;
/// Batches of different draws or facings filled at once while resolving (the pixels of a
/// tile alternate between them at silhouettes and where objects meet).
const OPEN: usize = 4;
/// How many triangles ahead of the one being filled the fill prefetches.
const PREFETCH_AHEAD: usize = 3;

/// A triangle of the tile's chunks: chunk index times 2^16 plus its index in the chunk
/// (a chunk holds at most [`CHUNK`](super::pipeline::CHUNK) = 2048 triangles).
pub(crate) type TriId = u32;

/// What the lanes of a batch share: the draw and facing, the varyings' count and the
/// derivatives' count.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Key {
    draw: u32,
    front: bool,
    stride: usize,
    derivatives: usize,
}

/// The visibility buffer of deferred shading: per pixel, the triangle of the last deferred
/// fragment that passed the depth test.
struct Vis {
    /// Whether any group has a live lane.
    pending: bool,
    /// Per group of eight pixels (tile offset / 8): the lanes holding a fragment.
    live: Vec<u32>,
    /// Per pixel: its fragment's triangle ([`TriId`]), meaningful where `live` says so.
    tri: Vec<u32>,
}

/// Each worker's fill state, kept from tile to tile (allocated once per thread): the
/// counters of the tile, the visibility buffer and the batches.
pub(crate) struct FillScratch {
    pub shaded: u64,
    pub depth_rejected: u64,
    /// Groups of eight lanes shaded.
    pub calls: u64,
    vis: Vis,
    /// The batches being filled while resolving, with their keys; the first also serves
    /// the forward path (the others are empty then).
    open: Vec<Batch>,
    keys: [Key; OPEN],
    /// Forward path: per group of `open[0]`, the depth at the pixel centres and the lanes
    /// that passed per sample.
    fz: [Lane; GROUPS],
    pass: [[u32; SAMPLES]; GROUPS],
    /// The kernel's interpolation ([`interp_group`]), set for each tile.
    interp: InterpFn,
    /// The shader's answers for the draw last asked about (cleared for each tile).
    info: Option<DrawInfo>,
}

impl Default for FillScratch {
    fn default() -> Self {
        Self {
            shaded: 0,
            depth_rejected: 0,
            calls: 0,
            vis: Vis {
                pending: false,
                live: vec![0; TILE_GROUPS],
                tri: vec![0; TILE_PIXELS],
            },
            open: (0..OPEN).map(|_| Batch::default()).collect(),
            keys: [Key::default(); OPEN],
            fz: [Lane::ZERO; GROUPS],
            pass: [[0; SAMPLES]; GROUPS],
            interp: interp_group::pick(crate::simd::KernelKind::Portable),
            info: None,
        }
    }
}

impl FillScratch {
    /// Ready for a new tile: counters zeroed (the visibility buffer and the batches are
    /// empty after every tile).
    fn begin_tile(&mut self) {
        self.shaded = 0;
        self.depth_rejected = 0;
        self.calls = 0;
    }
}

/// The fill's per-kernel functions, chosen once per pass.
#[derive(Clone, Copy)]
pub(crate) struct FillFns {
    deferred: fn(&mut Tile, &Rows<'_>, &mut FillScratch),
    direct: fn(&mut Tile, &Rows<'_>, &mut FillScratch),
    forward: fn(&mut Tile, &Rows<'_>, &mut FillScratch, &dyn FragmentShader),
    resolve: fn(&mut Tile, &[Chunk], &dyn FragmentShader, &mut FillScratch),
    interp: InterpFn,
    /// The tile's loop over its triangles ([`fill_tile_k`]), compiled per kernel too: its
    /// per-triangle work (bounds, edge values at the tile, classification) is scalar, but
    /// with the kernel's BMI and VEX encodings.
    pub(crate) tile: TileFn,
}

type TileFn = fn(&FillFns, &mut Tile, usize, &[Chunk], &dyn FragmentShader, &mut FillScratch);

impl FillFns {
    /// The functions of `kernel` (the portable ones if the CPU lacks it).
    pub(crate) fn pick(kernel: crate::simd::KernelKind) -> Self {
        Self {
            deferred: deferred::pick(kernel),
            direct: direct_tri::pick(kernel),
            forward: forward::pick(kernel),
            resolve: resolve::pick(kernel),
            interp: interp_group::pick(kernel),
            tile: fill_tile_k::pick(kernel),
        }
    }
}

crate::simd::per_kernel! {
    /// Fills tile number `index` with its binned triangles of `chunks`, in order, shading
    /// with `shader`; counts into `n`. The triangles' coverage, depth and shading run in the
    /// kernel's functions `f`, one call per triangle (and per resolve); this loop is one copy
    /// per kernel too, called through `f.tile`.
    fn fill_tile_k<L>(f: &FillFns, tile: &mut Tile, index: usize, chunks: &[Chunk], shader: &dyn FragmentShader, n: &mut FillScratch) {
        fill_tile_body(f, tile, index, chunks, shader, n);
    }
}

#[inline(always)]
fn fill_tile_body(
    f: &FillFns,
    tile: &mut Tile,
    index: usize,
    chunks: &[Chunk],
    shader: &dyn FragmentShader,
    n: &mut FillScratch,
) {
    n.begin_tile();
    n.interp = f.interp;
    n.info = None;
    for (ci, c) in chunks.iter().enumerate() {
        let bin = &c.bins[index];
        for (k, &i) in bin.iter().enumerate() {
            // Most of a small triangle's cost is fetching its set-up data (written by
            // another thread): prefetch the triangle 2 * AHEAD on, and the varyings of the
            // one AHEAD on (its triangle, read for their offset, is already here).
            if let Some(&far) = bin.get(k + 2 * PREFETCH_AHEAD) {
                prefetch(&c.tris[far as usize]);
            }
            if let Some(&near) = bin.get(k + PREFETCH_AHEAD) {
                let t = &c.tris[near as usize];
                let at = t.attr as usize;
                if let Some(a) = c.attrs.get(at..at + 3 * padded(t.stride as usize)) {
                    prefetch(a);
                }
            }
            let id: TriId = (ci as u32) << 16 | u32::from(i);
            let tri = &c.tris[i as usize];
            let Some(r) = rows(tile, tri, &c.attrs, id, shader, &mut n.info) else {
                continue;
            };
            match r.mode {
                Mode::Defer => (f.deferred)(tile, &r, n),
                Mode::Direct => (f.direct)(tile, &r, n),
                Mode::DepthOnly if tile.samples() == 1 => (f.deferred)(tile, &r, n),
                _ => {
                    // The deferred fragments are shaded before a triangle that is not
                    // deferred: it may blend with them, or discard lanes and leave them
                    // visible.
                    if n.vis.pending {
                        (f.resolve)(tile, chunks, shader, n);
                    }
                    (f.forward)(tile, &r, n, shader);
                }
            }
        }
    }
    if n.vis.pending {
        (f.resolve)(tile, chunks, shader, n);
    }
}

/// Triangle `id` of `chunks` and the varyings' array it indexes.
#[inline(always)]
fn lookup(chunks: &[Chunk], id: TriId) -> Option<(&SetupTri, &[f32])> {
    let c = chunks.get((id >> 16) as usize)?;
    Some((c.tris.get((id & 0xffff) as usize)?, &c.attrs[..]))
}

/// A triangle's varyings: vertex 0, differences to vertices 1 and 2 (each padded to a
/// multiple of 4), the number that are real, and the derivatives' constants if the shader
/// reads derivatives.
#[derive(Clone, Copy)]
pub(crate) struct Varyings<'a> {
    v0: &'a [f32],
    d1: &'a [f32],
    d2: &'a [f32],
    stride: usize,
    grad: Option<(usize, usize, Gradients)>,
}

/// What interpolating a triangle at a row of eight pixels needs: the triangle, the lane
/// offsets of its barycentrics along x, and its varyings.
#[derive(Clone, Copy)]
struct Interp<'a> {
    tri: &'a SetupTri,
    /// λ0, λ1, λ2 at the centre of the tile's first pixel, and per pixel along x and y.
    lt: [f32; 3],
    lx: [f32; 3],
    ly: [f32; 3],
    var: Varyings<'a>,
}

impl<'a> Interp<'a> {
    #[inline(always)]
    fn new(
        tri: &'a SetupTri,
        attrs: &'a [f32],
        derivatives: Option<(usize, usize)>,
        tile: (u32, u32),
    ) -> Option<Self> {
        let var = varyings(tri, attrs, derivatives)?;
        let inv = tri.inv_area;
        let lt = map3(|k| (edge_at(tri, k, tile.0, tile.1) - tri.bias(k)) as f32 * inv);
        let (lx, ly) = (
            map3(|k| (tri.ab(k).0 * ONE) as f32 * inv),
            map3(|k| (tri.ab(k).1 * ONE) as f32 * inv),
        );
        Some(Self {
            tri,
            lt,
            lx,
            ly,
            var,
        })
    }

    fn key(&self) -> Key {
        Key {
            draw: self.tri.info.draw,
            front: self.tri.info.front,
            stride: self.var.stride,
            derivatives: self.var.grad.map_or(0, |g| g.1),
        }
    }

    /// Screen-space barycentrics of eight pixels of a row: lane `i` is pixel `(dx + i, dy)`
    /// of the tile. Each λ from its own plane (1 - λ1 - λ2 cancels near vertex 0), from the
    /// tile's first pixel, so a pixel's value does not depend on which lane of which row
    /// computed it: every path (deferred, direct, forward, small triangles) gets the same
    /// bits.
    #[inline(always)]
    fn barycentrics<L: Level>(&self, dx: u32, dy: u32) -> [F8<L>; 3] {
        let x = F8::<L>::RAMP + F8::splat(dx as f32);
        let dy = dy as f32;
        let l = |k: usize| {
            mad(
                x,
                F8::splat(self.lx[k]),
                F8::splat(self.lt[k] + dy * self.ly[k]),
            )
        };
        [l(0), l(1), l(2)]
    }
}

/// How a triangle's fragments are handled.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Mode {
    /// Into the visibility buffer, shaded at the end of the tile.
    Defer,
    /// The colour is the interpolated varyings ([`FragmentShader::colour_is_varyings`]):
    /// written by the fill at the test, no shader called.
    Direct,
    /// Shaded by rows after the test, then written with the draw's blend.
    Forward,
    /// Depth only, written at the test, no shading.
    DepthOnly,
}

/// What the rows of one triangle share, computed once per triangle and tile.
struct Rows<'a> {
    tri: &'a SetupTri,
    /// The interpolation of a forward triangle (a deferred one is interpolated when the
    /// visibility buffer is resolved).
    it: Option<Interp<'a>>,
    /// Edge steps per pixel along y, and per lane offsets along x (in i32 instead when
    /// `narrow`, see `rows`; the i64 ones are only filled when not).
    step_y: [i64; 3],
    lane_x: [[i64; LANES]; 3],
    lane_x32: [[i32; LANES]; 3],
    narrow: bool,
    /// Depth at the centre of the tile's first pixel, and per pixel along x and y.
    zt: f32,
    zx: f32,
    zy: f32,
    mode: Mode,
    id: TriId,
}

impl Rows<'_> {
    /// `(RAMP + dx) zx`: the depth's change along a row from the tile's first column to
    /// the pixels of lanes starting at tile column `dx`.
    #[inline(always)]
    fn z_lanes<L: Level>(&self, dx: u32) -> F8<L> {
        (F8::RAMP + F8::splat(dx as f32)) * self.zx
    }

    /// The depth of eight pixels of tile row `dy` whose [`Rows::z_lanes`] are `x`: from the
    /// tile's first pixel, so (as for the barycentrics) a pixel's depth does not depend on
    /// the path or the lane that computes it. Clamped to the depth range [0, 1] (as
    /// hardware clamps to the viewport's): a triangle with a vertex at w = 1e30 has depth
    /// gradients so steep that the plane's rounding leaves the range by more than its width.
    #[inline(always)]
    fn z<L: Level>(&self, x: F8<L>, dy: u32) -> F8<L> {
        (x + F8::splat(self.zt + dy as f32 * self.zy)).clamp(0.0, 1.0)
    }
}

/// What the fill asks the shader about a draw, asked once per draw and tile.
#[derive(Clone, Copy, Debug)]
pub(crate) struct DrawInfo {
    draw: u32,
    defers: bool,
    discards: bool,
    colour_is_varyings: bool,
    derivatives: Option<(usize, usize)>,
}

impl DrawInfo {
    /// `shader`'s answers for `draw`.
    fn of(shader: &dyn FragmentShader, draw: u32) -> Self {
        Self {
            draw,
            defers: shader.defers(draw),
            discards: shader.discards(draw),
            colour_is_varyings: shader.colour_is_varyings(draw),
            derivatives: shader.derivatives(draw),
        }
    }
}

/// `shader`'s answers for `draw`, from `cache` when it holds that draw's.
#[inline(always)]
fn draw_info(cache: &mut Option<DrawInfo>, shader: &dyn FragmentShader, draw: u32) -> DrawInfo {
    match cache {
        Some(c) if c.draw == draw => *c,
        _ => *cache.insert(DrawInfo::of(shader, draw)),
    }
}

/// Per-triangle constants of a multisampled tile: each sample's offsets of the three edge
/// values and of the depth from those at the pixel centre.
struct Samples {
    edge: [[i64; 3]; SAMPLES],
    z: [f32; SAMPLES],
}

impl Samples {
    fn new(tri: &SetupTri) -> Self {
        // z = z0 + λ1 dz1 + λ2 dz2 with λ_k = E_k / area: per fixed unit along x,
        // dz/dx = (a_1 dz1 + a_2 dz2) / area; likewise along y with b.
        let dzdx = (tri.a[1] as f32 * tri.z[1] + tri.a[2] as f32 * tri.z[2]) * tri.inv_area;
        let dzdy = (tri.b[1] as f32 * tri.z[1] + tri.b[2] as f32 * tri.z[2]) * tri.inv_area;
        let mut out = Self {
            edge: [[0; 3]; SAMPLES],
            z: [0.0; SAMPLES],
        };
        for (s, o) in sample_offsets(SAMPLES as u32).iter().enumerate() {
            let (dx, dy) = (i64::from(o[0]) * (ONE / 16), i64::from(o[1]) * (ONE / 16));
            for k in 0..3 {
                let (a, b) = tri.ab(k);
                out.edge[s][k] = a * dx + b * dy;
            }
            out.z[s] = dzdx * dx as f32 + dzdy * dy as f32;
        }
        out
    }
}

/// The 8x8 blocks of the tile that the bounds of `r`'s triangle touch and its edges do not
/// exclude ([`Blocks::next`]), with sample points `reach` fixed units around the pixel
/// centres.
#[inline(always)]
fn walk(tile: &Tile, r: &Rows<'_>, reach: i64) -> Blocks {
    let tri = r.tri;
    let x0 = tri.x0.max(tile.x0);
    let y0 = tri.y0.max(tile.y0);
    let x1 = tri.x1.min(tile.x0 + tile.w - 1);
    let y1 = tri.y1.min(tile.y0 + tile.h - 1);
    let first_bx = x0 - x0.saturating_sub(tile.x0) % BLOCK;
    Blocks {
        x0,
        y0,
        x1,
        y1,
        first_bx,
        bx: first_bx,
        by: y0 - y0.saturating_sub(tile.y0) % BLOCK,
        reach,
    }
}

/// The blocks of [`walk`].
struct Blocks {
    x0: u32,
    y0: u32,
    x1: u32,
    y1: u32,
    first_bx: u32,
    bx: u32,
    by: u32,
    reach: i64,
}

impl Blocks {
    /// The next block the triangle's edges do not exclude: its `bx`, rows `y0..=y1`, lanes
    /// `span` inside the bounds, and whether its lanes need the edge test (not all inside).
    #[inline(always)]
    fn next(&mut self, tri: &SetupTri) -> Option<(u32, u32, u32, u32, bool)> {
        while self.by <= self.y1 {
            let bx = self.bx;
            let by = self.by;
            self.bx += BLOCK;
            if self.bx > self.x1 {
                self.bx = self.first_bx;
                self.by += BLOCK;
            }
            let (sx0, sy0) = (bx.max(self.x0), by.max(self.y0));
            let (sx1, sy1) = ((bx + BLOCK - 1).min(self.x1), (by + BLOCK - 1).min(self.y1));
            // Lanes of the block inside the triangle's (tile-clipped) bounds.
            let span = ((1u32 << (sx1 - bx + 1)) - 1) & !((1u32 << (sx0 - bx)) - 1);
            match classify(tri, self.reach, sx0, sy0, sx1, sy1) {
                Coverage::None => {}
                Coverage::Full => return Some((bx, sy0, sy1, span, false)),
                Coverage::Partial => return Some((bx, sy0, sy1, span, true)),
            }
        }
        None
    }
}

crate::simd::per_kernel! {
    /// A deferred (or, on a single-sample tile, depth-only) triangle: coverage and depth,
    /// into the visibility buffer.
    fn deferred<L>(tile: &mut Tile, r: &Rows<'_>, n: &mut FillScratch) {
        if let Some(b) = small_bounds(tile, r) {
            let c = match r.mode {
                Mode::Defer => small::<L, DEFER>(tile, r, n, b, Counts::default()),
                _ => small::<L, DEPTH>(tile, r, n, b, Counts::default()),
            };
            c.add_to(n);
            return;
        }
        let mut blocks = walk(tile, r, 0);
        let mut c = Counts::default();
        while let Some((bx, y0, y1, span, test)) = blocks.next(r.tri) {
            c = match (r.mode == Mode::Defer, test) {
                (true, true) => block::<L, true, DEFER>(tile, r, n, None, bx, y0, y1, span, c),
                (true, false) => block::<L, false, DEFER>(tile, r, n, None, bx, y0, y1, span, c),
                (false, true) => block::<L, true, DEPTH>(tile, r, n, None, bx, y0, y1, span, c),
                (false, false) => block::<L, false, DEPTH>(tile, r, n, None, bx, y0, y1, span, c),
            };
        }
        c.add_to(n);
    }
}

crate::simd::per_kernel! {
    /// A [`Mode::Direct`] triangle: coverage, depth and its interpolated colour, written at
    /// the test.
    fn direct_tri<L>(tile: &mut Tile, r: &Rows<'_>, n: &mut FillScratch) {
        if let Some(b) = small_bounds(tile, r) {
            small::<L, DIRECT>(tile, r, n, b, Counts::default()).add_to(n);
            return;
        }
        let mut blocks = walk(tile, r, 0);
        let mut c = Counts::default();
        while let Some((bx, y0, y1, span, test)) = blocks.next(r.tri) {
            c = if test {
                block::<L, true, DIRECT>(tile, r, n, None, bx, y0, y1, span, c)
            } else {
                block::<L, false, DIRECT>(tile, r, n, None, bx, y0, y1, span, c)
            };
        }
        c.add_to(n);
    }
}

crate::simd::per_kernel! {
    /// A forward triangle (or a depth-only one on a multisampled tile): coverage and depth,
    /// its rows shaded by batches and written with the draw's state.
    fn forward<L>(tile: &mut Tile, r: &Rows<'_>, n: &mut FillScratch, shader: &dyn FragmentShader) {
        let multi = (tile.samples() as usize == SAMPLES).then(|| Samples::new(r.tri));
        let mut blocks = walk(tile, r, sample_reach(tile.samples()));
        let mut c = Counts::default();
        let sh = Some(shader);
        while let Some((bx, y0, y1, span, test)) = blocks.next(r.tri) {
            c = match (&multi, test) {
                (None, true) => block::<L, true, FORWARD>(tile, r, n, sh, bx, y0, y1, span, c),
                (None, false) => block::<L, false, FORWARD>(tile, r, n, sh, bx, y0, y1, span, c),
                (Some(m), true) => block_ms::<L, true>(tile, r, m, n, shader, bx, y0, y1, span, c),
                (Some(m), false) => block_ms::<L, false>(tile, r, m, n, shader, bx, y0, y1, span, c),
            };
        }
        c.add_to(n);
        if r.mode == Mode::Forward && n.open[0].len > 0 {
            shade_forward::<L>(tile, r, multi.as_ref(), shader, n);
        }
    }
}

#[cfg(test)]
mod tests;
