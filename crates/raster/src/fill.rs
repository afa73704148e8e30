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

/// The per-triangle constants of `tri`'s rows in `tile`, or `None` if it has no pixel there
/// or its varyings are missing.
#[inline(always)]
fn rows<'a>(
    tile: &Tile,
    tri: &'a SetupTri,
    attrs: &'a [f32],
    id: TriId,
    shader: &dyn FragmentShader,
    cache: &mut Option<DrawInfo>,
) -> Option<Rows<'a>> {
    let x0 = tri.x0.max(tile.x0);
    let y0 = tri.y0.max(tile.y0);
    let x1 = tri.x1.min(tile.x0 + tile.w - 1);
    let y1 = tri.y1.min(tile.y0 + tile.h - 1);
    if x0 > x1 || y0 > y1 {
        return None;
    }
    let step_x = map3(|k| tri.ab(k).0 * ONE);
    let step_y = map3(|k| tri.ab(k).1 * ONE);
    // Coverage in i32 lanes ("narrow"): the lane offsets `a_k ONE i` (i < 8) stay below
    // 2^28 in magnitude when |a_k| < 2^17 (edges under 512 px across), and a row's edge
    // value clamped to [-2^30, 2^30] keeps its sign after adding them, without overflow.
    let narrow = (0..3).all(|k| tri.ab(k).0.abs() < 1 << 17);
    let mut lane_x = [[0i64; LANES]; 3];
    let mut lane_x32 = [[0i32; LANES]; 3];
    if narrow {
        for k in 0..3 {
            let step = step_x[k] as i32;
            for i in 0..LANES {
                lane_x32[k][i] = step * i as i32;
            }
        }
    } else {
        for k in 0..3 {
            for i in 0..LANES {
                lane_x[k][i] = step_x[k] * i as i64;
            }
        }
    }
    let st = tri.state;
    let info = draw_info(cache, shader, tri.info.draw);
    let replace = tile.samples() == 1 && st.color_write && st.blend == Blend::Replace;
    let mode = if !st.color_write && !info.discards {
        Mode::DepthOnly
    } else if replace && info.colour_is_varyings && tri.stride >= 3 {
        Mode::Direct
    } else if replace && info.defers {
        Mode::Defer
    } else {
        Mode::Forward
    };
    let it = if matches!(mode, Mode::Forward | Mode::Direct) {
        Some(Interp::new(
            tri,
            attrs,
            info.derivatives,
            (tile.x0, tile.y0),
        )?)
    } else {
        // (The varyings must be there when the visibility buffer is resolved.)
        varyings(tri, attrs, None)?;
        None
    };
    let inv = tri.inv_area;
    let s = ONE as f32 * inv;
    let zx = tri.a[1] as f32 * s * tri.z[1] + tri.a[2] as f32 * s * tri.z[2];
    let zy = tri.b[1] as f32 * s * tri.z[1] + tri.b[2] as f32 * s * tri.z[2];
    let l = |k: usize| (edge_at(tri, k, tile.x0, tile.y0) - tri.bias(k)) as f32 * inv;
    let zt = tri.z[0] + l(1) * tri.z[1] + l(2) * tri.z[2];
    Some(Rows {
        tri,
        it,
        step_y,
        lane_x,
        lane_x32,
        narrow,
        zt,
        zx,
        zy,
        mode,
        id,
    })
}

/// `tri`'s varyings in `attrs`, with the derivatives' constants if the shader reads
/// derivatives of its draw; `None` if they are missing.
#[inline(always)]
fn varyings<'a>(
    tri: &SetupTri,
    attrs: &'a [f32],
    derivatives: Option<(usize, usize)>,
) -> Option<Varyings<'a>> {
    let stride = tri.stride as usize;
    let row = padded(stride);
    let at = tri.attr as usize;
    let var = attrs.get(at..at + 3 * row)?;
    let grad = derivatives
        .filter(|&(first, count)| count > 0 && first + count <= stride)
        .map(|(first, count)| (first, count, Gradients::new(tri)));
    Some(Varyings {
        v0: &var[..row],
        d1: &var[row..2 * row],
        d2: &var[2 * row..],
        stride,
        grad,
    })
}

enum Coverage {
    None,
    Partial,
    Full,
}

/// `[f(0), f(1), f(2)]`, written out: `[0, 1, 2].map(f)` in the per-triangle set-up of a
/// tile was compiled out of line (`array::try_map`, 4-5% of a frame of small triangles).
#[inline(always)]
fn map3<T>(mut f: impl FnMut(usize) -> T) -> [T; 3] {
    [f(0), f(1), f(2)]
}

/// Edge function (biased) at the centre of pixel (x, y).
#[inline(always)]
fn edge_at(tri: &SetupTri, k: usize, x: u32, y: u32) -> i64 {
    let (a, b) = tri.ab(k);
    a * (i64::from(x) * ONE + HALF) + b * (i64::from(y) * ONE + HALF) + tri.c[k] + tri.bias(k)
}

/// Coverage of the pixels `x0..=x1` by `y0..=y1`: the extremes of each edge over the box of
/// their sample points (the pixel centres widened by `reach` fixed units on every side).
#[inline(always)]
fn classify(tri: &SetupTri, reach: i64, x0: u32, y0: u32, x1: u32, y1: u32) -> Coverage {
    let mut full = true;
    let dx = i64::from(x1 - x0) * ONE + 2 * reach;
    let dy = i64::from(y1 - y0) * ONE + 2 * reach;
    for k in 0..3 {
        let (a, b) = tri.ab(k);
        let e = edge_at(tri, k, x0, y0) - (a + b) * reach;
        let (ax, by) = (a * dx, b * dy);
        let max = e + ax.max(0) + by.max(0);
        let min = e + ax.min(0) + by.min(0);
        if max < 0 {
            return Coverage::None;
        }
        full &= min >= 0;
    }
    if full {
        Coverage::Full
    } else {
        Coverage::Partial
    }
}

/// Coverage and early depth of rows `y0..=y1` of the 8-pixel-wide block at `bx` (lanes
/// outside `span` are off). Deferred: the live lanes go to the visibility buffer (their
/// depth written now); forward: the rows with a live lane are interpolated into the
/// forward batch (`n.open[0]`), shaded when it is full; depth only: depth written now.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn block<L: Level, const TEST: bool, const MODE: u8>(
    tile: &mut Tile,
    r: &Rows<'_>,
    n: &mut FillScratch,
    shader: Option<&dyn FragmentShader>,
    bx: u32,
    y0: u32,
    y1: u32,
    span: u32,
    mut c: Counts,
) -> Counts {
    let tri = r.tri;
    let st = tri.state;
    let mut row = map3(|k| edge_at(tri, k, bx, y0));
    let dx = bx - tile.x0;
    let zl = r.z_lanes::<L>(dx);
    for y in y0..=y1 {
        let mut cover = span;
        if TEST {
            cover &= row_mask(r, row);
        }
        let dy = y - tile.y0;
        let o = (dy * TILE + dx) as usize;
        if cover != 0 {
            let z = r.z(zl, dy);
            let pass = depth_pass(st.depth_test, z, &tile.depth[o..o + LANES]);
            let live = cover & pass;
            c.rejected += (cover & !pass).count_ones();
            if live != 0 {
                match MODE {
                    DIRECT => {
                        if let Some(it) = &r.it {
                            direct::<L>(tile, it, dx, dy, o, live, z);
                            c.shaded += live.count_ones();
                            c.calls += 1;
                        }
                    }
                    DEFER | DEPTH => {
                        if st.depth_write {
                            // A deferred fragment is shaded later, maybe after other
                            // triangles: they must test against its depth now.
                            let d = &mut tile.depth[o..o + LANES];
                            z.store_where(M8::from_bits(live), d);
                        }
                        if MODE == DEFER {
                            record::<L>(&mut n.vis, o, live, r.id);
                        }
                    }
                    _ => {
                        if let Some(shader) = shader {
                            let mut pass = [0; SAMPLES];
                            pass[0] = live;
                            push_forward(tile, r, n, shader, None, (dx, dy), live, pass, z);
                        }
                    }
                }
            }
        }
        for k in 0..3 {
            row[k] += r.step_y[k];
        }
    }
    c
}

/// [`block`]'s modes: [`Mode::Defer`], [`Mode::Direct`], [`Mode::Forward`],
/// [`Mode::DepthOnly`] as constants, so each is a loop of its own.
const DEFER: u8 = 0;
const DIRECT: u8 = 1;
const FORWARD: u8 = 2;
const DEPTH: u8 = 3;

/// Counters of a triangle's fill, kept in registers and added to the tile's at its end.
#[derive(Clone, Copy, Default)]
struct Counts {
    rejected: u32,
    shaded: u32,
    calls: u32,
}

impl Counts {
    #[inline(always)]
    fn add_to(self, n: &mut FillScratch) {
        n.depth_rejected += u64::from(self.rejected);
        n.shaded += u64::from(self.shaded);
        n.calls += u64::from(self.calls);
    }
}

/// [`block`] on a multisampled tile (always forward): coverage and depth per sample (`m`);
/// the shader then runs once per row at the pixel centres and its colour goes to the
/// samples that passed.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn block_ms<L: Level, const TEST: bool>(
    tile: &mut Tile,
    r: &Rows<'_>,
    m: &Samples,
    n: &mut FillScratch,
    shader: &dyn FragmentShader,
    bx: u32,
    y0: u32,
    y1: u32,
    span: u32,
    mut c: Counts,
) -> Counts {
    let tri = r.tri;
    let st = tri.state;
    let mut row = map3(|k| edge_at(tri, k, bx, y0));
    for y in y0..=y1 {
        let mut cover = [span; SAMPLES];
        if TEST {
            for (c, e) in cover.iter_mut().zip(&m.edge) {
                *c &= row_mask(r, [row[0] + e[0], row[1] + e[1], row[2] + e[2]]);
            }
        }
        let any = cover.iter().fold(0, |a, c| a | c);
        let (dx, dy) = (bx - tile.x0, y - tile.y0);
        let o = (dy * TILE + dx) as usize;
        if any != 0 {
            let zc = r.z(r.z_lanes::<L>(dx), dy);
            let mut pass = [0u32; SAMPLES];
            for s in 0..SAMPLES {
                let d = &tile.depth[s * TILE_PIXELS + o..][..LANES];
                pass[s] = cover[s] & depth_pass(st.depth_test, (zc + m.z[s]).clamp(0.0, 1.0), d);
            }
            let live = pass.iter().fold(0, |a, p| a | p);
            c.rejected += (any & !live).count_ones();
            if live != 0 {
                if r.mode == Mode::DepthOnly {
                    if st.depth_write {
                        for s in 0..SAMPLES {
                            let d = &mut tile.depth[s * TILE_PIXELS + o..][..LANES];
                            let z = (zc + m.z[s]).clamp(0.0, 1.0);
                            z.store_where(M8::from_bits(pass[s]), d);
                        }
                    }
                } else {
                    push_forward(tile, r, n, shader, Some(m), (dx, dy), live, pass, zc);
                }
            }
        }
        for k in 0..3 {
            row[k] += r.step_y[k];
        }
    }
    c
}

/// Keeps lanes `live` of the row at tile offset `o` (a multiple of eight) for triangle `id`.
#[inline(always)]
fn record<L: Level>(vis: &mut Vis, o: usize, live: u32, id: TriId) {
    I8::<L>::splat(id as i32).store_where_u32(M8::from_bits(live), &mut vis.tri[o..o + LANES]);
    // A row of a small triangle need not start at a group: its lanes span two.
    let (g, sh) = (o / LANES, o % LANES);
    vis.live[g] |= (live << sh) & 0xFF;
    if sh != 0 {
        vis.live[g + 1] |= live >> (LANES - sh);
    }
    vis.pending = true;
}

/// The pixel bounds of a small triangle in the tile (`x0, y0, x1, y1`, inclusive): one whose
/// bounds there are at most eight pixels wide and whose eight lanes from `x0` stay in the
/// tile's row, so one eight-lane step per row covers it without walking blocks; `None` for
/// the others (and for the cases the small path does not handle: wide edges, several
/// samples).
#[inline(always)]
fn small_bounds(tile: &Tile, r: &Rows<'_>) -> Option<(u32, u32, u32, u32)> {
    let tri = r.tri;
    let x0 = tri.x0.max(tile.x0);
    let x1 = tri.x1.min(tile.x0 + tile.w - 1);
    let ok = r.narrow && tile.samples() == 1 && x1 - x0 < BLOCK && x0 - tile.x0 <= TILE - BLOCK;
    ok.then(|| {
        (
            x0,
            tri.y0.max(tile.y0),
            x1,
            tri.y1.min(tile.y0 + tile.h - 1),
        )
    })
}

/// A small triangle ([`small_bounds`]) of mode `MODE` (deferred, depth only or direct): one
/// eight-lane step per row of its bounds, its lanes starting at its first column (not at a
/// group's), with the same per-pixel values as [`block`] (the planes are the tile's).
#[inline(always)]
fn small<L: Level, const MODE: u8>(
    tile: &mut Tile,
    r: &Rows<'_>,
    n: &mut FillScratch,
    (x0, y0, x1, y1): (u32, u32, u32, u32),
    mut c: Counts,
) -> Counts {
    let tri = r.tri;
    let st = tri.state;
    let span = (1u32 << (x1 - x0 + 1)) - 1;
    let mut row = map3(|k| edge_at(tri, k, x0, y0));
    let dx = x0 - tile.x0;
    let zl = r.z_lanes::<L>(dx);
    for y in y0..=y1 {
        let cover = span & row_mask(r, row);
        if cover != 0 {
            let dy = y - tile.y0;
            let o = (dy * TILE + dx) as usize;
            let z = r.z(zl, dy);
            let pass = depth_pass(st.depth_test, z, &tile.depth[o..o + LANES]);
            let live = cover & pass;
            c.rejected += (cover & !pass).count_ones();
            if live != 0 {
                if MODE == DIRECT {
                    if let Some(it) = &r.it {
                        direct::<L>(tile, it, dx, dy, o, live, z);
                        c.shaded += live.count_ones();
                        c.calls += 1;
                    }
                } else {
                    if st.depth_write {
                        z.store_where(M8::from_bits(live), &mut tile.depth[o..o + LANES]);
                    }
                    if MODE == DEFER {
                        record::<L>(&mut n.vis, o, live, r.id);
                    }
                }
            }
        }
        for k in 0..3 {
            row[k] += r.step_y[k];
        }
    }
    c
}

/// A row of a [`Mode::Direct`] triangle: its first three varyings, interpolated at the row's
/// pixels, are the colour of the lanes `live` (alpha 1), and `z` their depth (written when
/// the draw writes depth). The same interpolation as the shaded paths.
#[inline(always)]
fn direct<L: Level>(
    tile: &mut Tile,
    it: &Interp<'_>,
    dx: u32,
    dy: u32,
    o: usize,
    live: u32,
    z: F8<L>,
) {
    let tri = it.tri;
    let [p1, p2, _] = perspective(tri, it.barycentrics::<L>(dx, dy));
    let m = M8::<L>::from_bits(live);
    let full = live & 0xFF == 0xFF;
    let v = &it.var;
    let (color, depth) = tile.planes_mut();
    for c in 0..4 {
        let val = if c < 3 {
            mad(
                F8::splat(v.d2[c]),
                p2,
                mad(F8::splat(v.d1[c]), p1, F8::splat(v.v0[c])),
            )
        } else {
            F8::ONE
        };
        let plane = &mut color[c * TILE_PIXELS + o..][..LANES];
        if full {
            val.store(plane);
        } else {
            val.store_where(m, plane);
        }
    }
    if tri.state.depth_write {
        let d = &mut depth[o..o + LANES];
        if full {
            z.store(d);
        } else {
            z.store_where(m, d);
        }
    }
}

/// Adds a row of the current forward triangle to the forward batch, interpolated at
/// barycentrics `l`, with its centre depth `z` and per-sample lanes `pass`; shades the batch
/// when it is full.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn push_forward<L: Level>(
    tile: &mut Tile,
    r: &Rows<'_>,
    n: &mut FillScratch,
    shader: &dyn FragmentShader,
    m: Option<&Samples>,
    (dx, dy): (u32, u32),
    live: u32,
    pass: [u32; SAMPLES],
    z: F8<L>,
) {
    let Some(it) = &r.it else {
        return;
    };
    let o = dy * TILE + dx;
    n.shaded += u64::from(live.count_ones());
    let b = &mut n.open[0];
    if b.len == 0 {
        let key = it.key();
        b.start(tile, key.draw, key.front, key.stride, key.derivatives);
    }
    let g = b.len;
    b.len += 1;
    b.o[g] = o;
    b.mask[g] = live;
    n.fz[g] = z.into();
    n.pass[g] = pass;
    let out = GroupOut {
        var: &mut b.var[g],
        ddx: &mut b.ddx[g],
        ddy: &mut b.ddy[g],
    };
    let l = it.barycentrics::<L>(dx, dy).map(Lane::from);
    (n.interp)(r.tri, &l, &it.var, out, 0xFF);
    if b.len == GROUPS {
        shade_forward::<L>(tile, r, m, shader, n);
    }
}

/// Shades the forward batch and writes what the shader keeps with the triangle's draw
/// state: to the one sample of a plain tile, or to the samples that passed of a
/// multisampled one (`m`).
#[inline(always)]
fn shade_forward<L: Level>(
    tile: &mut Tile,
    r: &Rows<'_>,
    m: Option<&Samples>,
    shader: &dyn FragmentShader,
    n: &mut FillScratch,
) {
    let b = &mut n.open[0];
    n.calls += b.len as u64;
    let live = b.mask;
    shader.shade(b);
    let st = r.tri.state;
    for g in 0..b.len {
        let keep = b.mask[g] & live[g];
        if keep == 0 {
            continue;
        }
        let o = b.o[g] as usize;
        match m {
            None => write(tile, st, 0, o, keep, &b.out[g], n.fz[g].get::<L>()),
            Some(m) => {
                for s in 0..SAMPLES {
                    let k = keep & n.pass[g][s];
                    if k != 0 {
                        write(
                            tile,
                            st,
                            s,
                            o,
                            k,
                            &b.out[g],
                            (n.fz[g].get::<L>() + m.z[s]).clamp(0.0, 1.0),
                        );
                    }
                }
            }
        }
    }
    b.len = 0;
}

crate::simd::per_kernel! {
    /// Shades the deferred fragments of the tile (see the module docs): each group of eight
    /// pixels with a live lane, triangle by triangle, interpolated into the open batch of
    /// its draw and facing; a batch is shaded when it has no room for another group, and
    /// all of them at the end.
    fn resolve<L>(tile: &mut Tile, chunks: &[Chunk], shader: &dyn FragmentShader, n: &mut FillScratch) {
        resolve_body::<L>(tile, chunks, shader, n);
    }
}

#[inline(always)]
fn resolve_body<L: Level>(
    tile: &mut Tile,
    chunks: &[Chunk],
    shader: &dyn FragmentShader,
    n: &mut FillScratch,
) {
    // The triangle of the last fragments looked up, and its key.
    let mut cur: Option<(TriId, Interp<'_>, Key)> = None;
    for group in 0..TILE_GROUPS {
        let mut rest = std::mem::take(&mut n.vis.live[group]);
        if rest == 0 {
            continue;
        }
        n.shaded += u64::from(rest.count_ones());
        let o = group * LANES;
        let (x, y) = (tile.x0 + (o as u32 % TILE), tile.y0 + o as u32 / TILE);
        while rest != 0 {
            let id = n.vis.tri[o + rest.trailing_zeros() as usize];
            let mask = same::<L>(&n.vis.tri[o..o + LANES], id) & rest;
            rest &= !mask;
            if cur.as_ref().is_none_or(|c| c.0 != id) {
                // Written without closures: `and_then`'s was compiled out of line, without
                // the kernel's features.
                cur = None;
                if let Some((tri, attrs)) = lookup(chunks, id) {
                    let info = draw_info(&mut n.info, shader, tri.info.draw);
                    let from = (tile.x0, tile.y0);
                    if let Some(it) = Interp::new(tri, attrs, info.derivatives, from) {
                        let key = it.key();
                        cur = Some((id, it, key));
                    }
                }
            }
            // (Every recorded triangle has its varyings: `rows` checked.)
            let Some((_, it, key)) = &cur else {
                continue;
            };
            let slot = open_batch::<L>(tile, shader, n, *key);
            let b = &mut n.open[slot];
            let g = if b.len > 0 && b.o[b.len - 1] as usize == o {
                b.len - 1
            } else {
                if b.len == GROUPS {
                    flush_deferred::<L>(tile, shader, &mut n.open[slot], &mut n.calls);
                }
                let b = &mut n.open[slot];
                if b.len == 0 {
                    b.start(tile, key.draw, key.front, key.stride, key.derivatives);
                }
                let g = b.len;
                b.len += 1;
                b.o[g] = o as u32;
                b.mask[g] = 0;
                g
            };
            let b = &mut n.open[slot];
            b.mask[g] |= mask;
            let tri = it.tri;
            let l = it
                .barycentrics::<L>(x - tile.x0, y - tile.y0)
                .map(Lane::from);
            let out = GroupOut {
                var: &mut b.var[g],
                ddx: &mut b.ddx[g],
                ddy: &mut b.ddy[g],
            };
            (n.interp)(tri, &l, &it.var, out, mask);
        }
    }
    for slot in 0..OPEN {
        if n.open[slot].len > 0 {
            flush_deferred::<L>(tile, shader, &mut n.open[slot], &mut n.calls);
        }
    }
    n.vis.pending = false;
}

/// The open batch for `key`: one holding it, else an empty one, else the fullest one shaded
/// and emptied.
#[inline(always)]
fn open_batch<L: Level>(
    tile: &mut Tile,
    shader: &dyn FragmentShader,
    n: &mut FillScratch,
    key: Key,
) -> usize {
    if let Some(i) = (0..OPEN).find(|&i| n.open[i].len > 0 && n.keys[i] == key) {
        return i;
    }
    let i = match (0..OPEN).find(|&i| n.open[i].len == 0) {
        Some(i) => i,
        None => {
            let i = (0..OPEN).max_by_key(|&i| n.open[i].len).unwrap_or(0);
            flush_deferred::<L>(tile, shader, &mut n.open[i], &mut n.calls);
            i
        }
    };
    n.keys[i] = key;
    i
}

/// Shades a batch of deferred fragments and writes their colours (their depth is written).
#[inline(always)]
fn flush_deferred<L: Level>(
    tile: &mut Tile,
    shader: &dyn FragmentShader,
    b: &mut Batch,
    calls: &mut u64,
) {
    *calls += b.len as u64;
    let live = b.mask;
    shader.shade(b);
    let (color, _) = tile.planes_mut();
    for g in 0..b.len {
        let keep = b.mask[g] & live[g];
        if keep != 0 {
            store_color::<L>(color, b.o[g] as usize, keep, &b.out[g]);
        }
    }
    b.len = 0;
}

/// The lanes of `t` (eight triangle ids) equal to `id`.
#[inline(always)]
fn same<L: Level>(t: &[u32], id: u32) -> u32 {
    I8::<L>::load_u32(t).eq(I8::splat(id as i32)).bits()
}

/// Lanes of a row whose (biased) edge values at lane 0 are `row` that lie inside all three
/// edges: bit `i` for lane `i` (bits above the eighth are set; the caller masks them).
#[inline(always)]
fn row_mask(r: &Rows<'_>, row: [i64; 3]) -> u32 {
    // A lane is out if any edge value is negative: OR the three values and read the sign
    // bits with MOVMSKPS (`edge_signs`, `M8::bits`); a loop gathering them bit by bit, or
    // the portable i32 loop, stayed scalar.
    if r.narrow {
        // Exact in i32 (see `narrow`): one 8 x i32 register per edge.
        let clamp = |v: i64| v.clamp(-(1 << 30), 1 << 30) as i32;
        let row32 = [clamp(row[0]), clamp(row[1]), clamp(row[2])];
        return !edge_signs(row32, &r.lane_x32) & 0xFF;
    }
    let mut out = 0;
    for i in 0..LANES {
        let w = (row[0] + r.lane_x[0][i]) | (row[1] + r.lane_x[1][i]) | (row[2] + r.lane_x[2][i]);
        out |= u32::from(w >= 0) << i;
    }
    out | !0xFF
}

/// Lanes where depth `z` passes `test` against the stored `depth` (eight values).
#[inline(always)]
fn depth_pass<L: Level>(test: DepthTest, z: F8<L>, depth: &[f32]) -> u32 {
    let depth = F8::load(depth);
    match test {
        DepthTest::Greater => z.gt(depth).bits(),
        DepthTest::GreaterEqual => z.ge(depth).bits(),
        DepthTest::Always => u32::MAX,
    }
}

/// The perspective weights `[p_1, p_2, 1 / D]` of `tri` at screen-space barycentrics `l`.
#[inline(always)]
fn perspective<L: Level>(tri: &SetupTri, l: [F8<L>; 3]) -> [F8<L>; 3] {
    // Perspective weights p_k = λ_k (1/w_k) / Σ λ_j (1/w_j). Inside the triangle every λ is
    // >= 0 (clamped against rounding), so every term of D is >= 0: no cancellation, and D > 0
    // even where one 1/w is tiny (a vertex at w = 1e30).
    let (l0, l1, l2) = (l[0].max(F8::ZERO), l[1].max(F8::ZERO), l[2].max(F8::ZERO));
    let w1 = l1 * tri.iw[1];
    let w2 = l2 * tri.iw[2];
    let d = mad(l0, F8::splat(tri.iw[0]), w1 + w2);
    let inv_d = d.recip();
    // Pinned: every varying reads them (see `F8::pin`).
    [w1 * inv_d, w2 * inv_d, inv_d]
}

/// Where a group's interpolated values go: its varyings and their derivatives.
pub(crate) struct GroupOut<'a> {
    var: &'a mut [Lane; MAX_VARYINGS],
    ddx: &'a mut [Lane; MAX_VARYINGS],
    ddy: &'a mut [Lane; MAX_VARYINGS],
}

/// A kernel's copy of [`interp_group`].
pub(crate) type InterpFn = fn(&SetupTri, &[Lane; 3], &Varyings<'_>, GroupOut<'_>, u32);

crate::simd::per_kernel! {
    /// Interpolates triangle `tri`'s varyings `v` (and their derivatives, if the draw asks) at
    /// screen-space barycentrics `l` into the lanes `mask` of `out` (the others keep what
    /// they hold).
    ///
    /// A function of its own, called per group: inlined into the resolve loop, LLVM
    /// vectorized the varyings' loop across four varyings and rebuilt the perspective
    /// weights lane by lane (eight `divss` for one `vdivps`); alone, every step is one
    /// eight-lane instruction.
    pub(crate) fn interp_group<L>(tri: &SetupTri, l: &[Lane; 3], v: &Varyings<'_>, out: GroupOut<'_>, mask: u32) {
        let [p1, p2, inv_d] = perspective::<L>(tri, [l[0].get(), l[1].get(), l[2].get()]);
        let m = M8::<L>::from_bits(mask);
        let n = v.stride.min(MAX_VARYINGS).min(v.v0.len()).min(v.d1.len()).min(v.d2.len());
        let var = out.var;
        for j in 0..n {
            let val = mad(
                F8::splat(v.d2[j]),
                p2,
                mad(F8::splat(v.d1[j]), p1, F8::splat(v.v0[j])),
            );
            var[j].blend(m, val);
        }
        if let Some((first, count, gr)) = &v.grad {
            let [d1x, d2x, d1y, d2y] = gr.weights(p1, p2, inv_d);
            let d1 = v.d1.get(*first..).unwrap_or(&[]);
            let d2 = v.d2.get(*first..).unwrap_or(&[]);
            let n = (*count).min(MAX_VARYINGS).min(d1.len()).min(d2.len());
            let (ddx, ddy) = (out.ddx, out.ddy);
            for j in 0..n {
                let (a, c) = (F8::splat(d1[j]), F8::splat(d2[j]));
                ddx[j].blend(m, mad(a, d1x, c * d2x));
                ddy[j].blend(m, mad(a, d1y, c * d2y));
            }
        }
    }
}

/// Writes colour `out` to the `keep` lanes at offset `o` of the (first sample's) colour
/// planes.
#[inline(always)]
fn store_color<L: Level>(color: &mut [f32], o: usize, keep: u32, out: &Colors) {
    let (cr, rest) = color.split_at_mut(TILE_PIXELS);
    let (cg, rest) = rest.split_at_mut(TILE_PIXELS);
    let (cb, rest) = rest.split_at_mut(TILE_PIXELS);
    let ca = &mut rest[..TILE_PIXELS];
    let planes = [
        (&mut cr[o..o + LANES], &out.r),
        (&mut cg[o..o + LANES], &out.g),
        (&mut cb[o..o + LANES], &out.b),
        (&mut ca[o..o + LANES], &out.a),
    ];
    if keep & 0xFF == 0xFF {
        for (p, v) in planes {
            p.copy_from_slice(&v.0);
        }
    } else {
        let m = M8::<L>::from_bits(keep);
        for (p, v) in planes {
            v.get::<L>().store_where(m, p);
        }
    }
}

/// Writes colour `out` and depth `z` to the `keep` lanes of sample `s` at offset `o`, as the
/// draw state says (blend, colour and depth writes).
#[inline(always)]
fn write<L: Level>(
    tile: &mut Tile,
    st: DrawState,
    s: usize,
    o: usize,
    keep: u32,
    out: &Colors,
    z: F8<L>,
) {
    let keep_m = M8::from_bits(keep);
    let full = keep & 0xFF == 0xFF;
    let (color, depth) = tile.planes_mut();
    if st.color_write {
        let color = &mut color[4 * s * TILE_PIXELS..];
        if st.blend == Blend::Replace {
            store_color::<L>(color, o, keep, out);
        } else {
            let (cr, rest) = color.split_at_mut(TILE_PIXELS);
            let (cg, rest) = rest.split_at_mut(TILE_PIXELS);
            let (cb, rest) = rest.split_at_mut(TILE_PIXELS);
            let ca = &mut rest[..TILE_PIXELS];
            let dst = [
                &mut cr[o..o + LANES],
                &mut cg[o..o + LANES],
                &mut cb[o..o + LANES],
                &mut ca[o..o + LANES],
            ];
            blend(st.blend, keep_m, out, dst);
        }
    }
    if st.depth_write {
        let depth = &mut depth[s * TILE_PIXELS + o..][..LANES];
        if full {
            z.store(depth);
        } else {
            z.store_where(keep_m, depth);
        }
    }
}

/// Blends `out` into the eight pixels of the four colour planes `dst` where `keep` is set.
#[inline(always)]
fn blend<L: Level>(mode: Blend, keep: M8<L>, out: &Colors, dst: [&mut [f32]; 4]) {
    let [pr, pg, pb, pa] = dst;
    let (dr, dg, db, da) = (F8::load(pr), F8::load(pg), F8::load(pb), F8::load(pa));
    let (sr, sg, sb, sa) = (out.r.get(), out.g.get(), out.b.get(), out.a.get());
    let (r2, g2, b2, a2) = match mode {
        Blend::Replace => (sr, sg, sb, sa),
        Blend::Alpha => {
            let a = sa.clamp(0.0, 1.0);
            let na = F8::ONE - a;
            (
                mad(sr, a, dr * na),
                mad(sg, a, dg * na),
                mad(sb, a, db * na),
                mad(da, na, a),
            )
        }
        Blend::Add => (sr + dr, sg + dg, sb + db, sa + da),
    };
    r2.store_where(keep, pr);
    g2.store_where(keep, pg);
    b2.store_where(keep, pb);
    a2.store_where(keep, pa);
}

/// Per-triangle constants of the perspective weights' derivatives (see the module docs).
#[derive(Clone, Copy, Default)]
pub(crate) struct Gradients {
    /// `∂λ_k/∂x (1/w_k)` and `∂λ_k/∂y (1/w_k)` for k = 1, 2.
    cx: [f32; 2],
    cy: [f32; 2],
    /// `∂D/∂x`, `∂D/∂y`.
    dx: f32,
    dy: f32,
}

impl Gradients {
    #[inline(always)]
    fn new(tri: &SetupTri) -> Self {
        let s = ONE as f32 * tri.inv_area;
        let (l1x, l2x) = (tri.a[1] as f32 * s, tri.a[2] as f32 * s);
        let (l1y, l2y) = (tri.b[1] as f32 * s, tri.b[2] as f32 * s);
        let (e1, e2) = (tri.iw[1] - tri.iw[0], tri.iw[2] - tri.iw[0]);
        Self {
            cx: [l1x * tri.iw[1], l2x * tri.iw[2]],
            cy: [l1y * tri.iw[1], l2y * tri.iw[2]],
            dx: l1x * e1 + l2x * e2,
            dy: l1y * e1 + l2y * e2,
        }
    }

    /// `[∂p_1/∂x, ∂p_2/∂x, ∂p_1/∂y, ∂p_2/∂y]` at lanes with perspective weights `p1`, `p2`
    /// and `inv = 1 / D`.
    #[inline(always)]
    fn weights<L: Level>(&self, p1: F8<L>, p2: F8<L>, inv: F8<L>) -> [F8<L>; 4] {
        let f = |c: f32, p: F8<L>, d: f32| mad(p, F8::splat(-d), F8::splat(c)) * inv;
        [
            f(self.cx[0], p1, self.dx),
            f(self.cx[1], p2, self.dx),
            f(self.cy[0], p1, self.dy),
            f(self.cy[1], p2, self.dy),
        ]
    }
}

#[cfg(test)]
mod tests {
    use glam::{Mat4, Vec2, Vec3, Vec4};

    use crate::simd::kernel::__private::Portable;
    use crate::simd::F8;

    type P = F8<Portable>;
    use crate::{
        draw, Batch, Colors, Cull, Draw, DrawState, FragmentShader, PerPixel, PixelShader, Stats,
        Target, TriInfo,
    };
    use realist_scene::Camera;

    /// Outputs the interpolated varying (alpha 1 marks coverage).
    struct Value;

    impl PixelShader for Value {
        fn pixel(&self, _: TriInfo, v: &[f32]) -> Option<Vec4> {
            Some(Vec4::new(v[0], v[1], 0.0, 1.0))
        }
    }

    /// Outputs the varying's derivatives (dx.x, dx.y, dy.x, dy.y).
    struct Derivatives;

    impl FragmentShader for Derivatives {
        fn derivatives(&self, _: u32) -> Option<(usize, usize)> {
            Some((0, 2))
        }
        fn shade(&self, b: &mut Batch) {
            assert_eq!(b.derivatives, 2);
            for g in 0..b.len {
                b.out[g] = Colors {
                    r: b.ddx[g][0],
                    g: b.ddx[g][1],
                    b: b.ddy[g][0],
                    a: b.ddy[g][1],
                };
            }
        }
    }

    const W: u32 = 96;
    const H: u32 = 72;

    fn render<S: FragmentShader>(clip: &[Vec4], var: &[Vec2], shader: &S) -> (Vec<Vec4>, Stats) {
        let flat: Vec<f32> = var.iter().flat_map(|v| [v.x, v.y]).collect();
        let mut target = Target::new(W, H, Vec4::ZERO);
        let mut stats = Stats::default();
        let d = Draw {
            id: 0,
            clip,
            varyings: &flat,
            stride: 2,
            triangles: &[[0, 1, 2]],
            state: DrawState {
                cull: Cull::None,
                ..DrawState::opaque()
            },
        };
        draw(&mut target, &[d], shader, &mut stats);
        (target.resolve().color, stats)
    }

    /// Compares the analytic derivatives with central differences of the rendered varying
    /// at every pixel whose four neighbours are covered; returns (pixels checked, worst
    /// error relative to the derivative's size).
    fn check(clip: &[Vec4], var: &[Vec2]) -> (usize, f32, Stats) {
        let (value, stats) = render(clip, var, &PerPixel(Value));
        let (grad, _) = render(clip, var, &Derivatives);
        let at = |x: u32, y: u32| value[(y * W + x) as usize];
        let (mut n, mut worst) = (0, 0f32);
        for y in 1..H - 1 {
            for x in 1..W - 1 {
                let nb = [at(x - 1, y), at(x + 1, y), at(x, y - 1), at(x, y + 1)];
                if at(x, y).w != 1.0 || nb.iter().any(|c| c.w != 1.0) {
                    continue;
                }
                let fdx = (nb[1] - nb[0]).truncate().truncate() * 0.5;
                let fdy = (nb[3] - nb[2]).truncate().truncate() * 0.5;
                let g = grad[(y * W + x) as usize];
                let (gx, gy) = (Vec2::new(g.x, g.y), Vec2::new(g.z, g.w));
                for (fd, an) in [(fdx, gx), (fdy, gy)] {
                    let scale = an.length().max(1e-3);
                    worst = worst.max((fd - an).length() / scale);
                }
                n += 1;
            }
        }
        (n, worst, stats)
    }

    fn camera_mvp() -> Mat4 {
        // Looking down at a floor, yawed and rolled: 1/w varies strongly along both x and y.
        let cam = Camera {
            eye: Vec3::new(0.0, 1.0, 0.0),
            target: Vec3::new(0.5, 0.0, -1.6),
            up: Vec3::new(0.4, 1.0, 0.0),
            yfov: 60f32.to_radians(),
            near: 0.05,
            ..Camera::default()
        };
        cam.projection(W as f32 / H as f32) * cam.view()
    }

    /// A non-finite vertex in a triangle that needs clipping (another vertex far outside
    /// the guard band and behind the eye) is culled as degenerate, whichever vertex it is,
    /// and draws nothing; so is one whose other vertices are inside.
    #[test]
    fn a_non_finite_vertex_culls_its_triangle_on_every_path() {
        let good = [
            Vec4::new(-0.5, -0.5, 0.5, 1.0),
            Vec4::new(0.5, -0.5, 0.5, 1.0),
        ];
        let far = Vec4::new(1e6, 0.2, 0.5, 1.0);
        let behind = Vec4::new(0.1, 0.2, 0.5, -1.0);
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            let nan = Vec4::new(bad, 0.0, 0.5, 1.0);
            for tri in [
                [nan, far, behind],
                [far, nan, good[0]],
                [good[0], behind, nan],
                [good[0], good[1], nan],
            ] {
                let (image, stats) = render(&tri, &[Vec2::ZERO; 3], &PerPixel(Value));
                assert_eq!(stats.culled_degenerate, 1, "{tri:?}");
                assert_eq!((stats.drawn, stats.clipped), (0, 0), "{tri:?}");
                assert!(image.iter().all(|c| *c == Vec4::ZERO), "{tri:?}");
            }
        }
    }

    #[test]
    fn analytic_derivatives_match_central_differences() {
        let mvp = camera_mvp();
        let world = [
            Vec3::new(-3.0, 0.0, -1.0),
            Vec3::new(2.5, 0.0, -0.6),
            Vec3::new(0.3, 0.0, -9.0),
        ];
        let clip: Vec<Vec4> = world.iter().map(|p| mvp * p.extend(1.0)).collect();
        let var: Vec<Vec2> = world
            .iter()
            .map(|p| Vec2::new(p.x * 3.0, p.z * 2.0))
            .collect();
        let (n, worst, stats) = check(&clip, &var);
        eprintln!("unclipped: {n} pixels, worst relative error {worst}");
        assert_eq!(stats.clipped, 0);
        assert!(n > 1000, "{n} pixels");
        // Central differences of the rational varying are exact to second order; the
        // affine (not perspective-correct) derivative is off by far more.
        assert!(worst < 0.02, "worst relative error {worst} over {n} pixels");
    }

    #[test]
    fn clipped_pieces_get_the_derivatives_of_the_whole_triangle() {
        // The floor triangle reaches behind the eye: near-plane clipping cuts it into
        // pieces, each set up with its own (clip-space interpolated) vertices.
        let mvp = camera_mvp();
        let world = [
            Vec3::new(-1.0, 0.0, 3.0),
            Vec3::new(4.0, 0.0, -1.2),
            Vec3::new(-2.5, 0.0, -7.0),
        ];
        let clip: Vec<Vec4> = world.iter().map(|p| mvp * p.extend(1.0)).collect();
        assert!(
            clip[0].w < 0.0 && clip[1].w > 0.0 && clip[2].w > 0.0,
            "{clip:?}"
        );
        let var: Vec<Vec2> = world
            .iter()
            .map(|p| Vec2::new(p.x * 3.0, p.z * 2.0))
            .collect();
        let (n, worst, stats) = check(&clip, &var);
        eprintln!("clipped: {n} pixels, worst relative error {worst}, {stats:?}");
        assert_eq!(stats.clipped, 1);
        assert!(stats.drawn >= 2, "{stats:?}");
        assert!(n > 1000, "{n} pixels");
        assert!(worst < 0.02, "worst relative error {worst} over {n} pixels");
    }

    /// A lane shader with a nonlinear colour of its varyings, their derivatives and the
    /// facing, deferred or not.
    struct Wavy {
        pack: bool,
    }

    impl FragmentShader for Wavy {
        fn derivatives(&self, _: u32) -> Option<(usize, usize)> {
            Some((0, 2))
        }
        fn defers(&self, _: u32) -> bool {
            self.pack
        }
        fn discards(&self, _: u32) -> bool {
            false
        }
        fn shade(&self, b: &mut Batch) {
            let side = if b.front { 1.0 } else { 0.5 };
            for g in 0..b.len {
                let (u, v): (P, P) = (b.var[g][0].get(), b.var[g][1].get());
                let (dx, dy): (P, P) = (b.ddx[g][0].get(), b.ddy[g][1].get());
                b.out[g] = Colors::of(
                    (u * P::splat(7.0) + v).map(f32::sin),
                    (dx * P::splat(31.0)).map(f32::cos) * side,
                    dy * P::splat(13.0) + P::splat(b.draw as f32),
                    (u * v).sqrt(),
                );
            }
        }
    }

    /// Deferring fragments to the tile's end and packing them across rows, triangles and
    /// draws changes no pixel: thousands of small triangles of two draws, both facings, in
    /// perspective and overlapping in depth, render bit for bit as shaded in order, with
    /// each covered pixel shaded once and far fewer shader calls.
    #[test]
    fn deferred_shading_gives_the_forward_image() {
        let mut seed = 0x2545_f491_u32;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f32 / u32::MAX as f32
        };
        let (mut clip, mut var) = (Vec::new(), Vec::new());
        for t in 0..6000 {
            let (cx, cy, w) = (rnd() * 2.2 - 1.1, rnd() * 2.2 - 1.1, 0.5 + rnd() * 3.0);
            let z = rnd() * 0.8 + 0.1;
            // Counter-clockwise around the centre (front-facing), one in ten clockwise.
            let turn = if t % 10 == 0 { -1.0 } else { 1.0 };
            for k in 0..3 {
                let a = turn * (k as f32 + rnd() * 0.5) * std::f32::consts::TAU / 3.0;
                // Mostly small (rows with a lane or two), some large (full rows, shaded
                // as they are unless a packed fragment shares their pixels).
                let r = if t % 7 == 0 {
                    0.1 + rnd() * 0.3
                } else {
                    0.02 + rnd() * 0.05
                };
                let (x, y) = (cx + r * a.cos(), cy + r * a.sin());
                clip.push(Vec4::new(x * w, y * w, z * w, w));
                var.extend([rnd() * 4.0, rnd() * 4.0]);
            }
        }
        let tris: Vec<[u32; 3]> = (0..clip.len() as u32 / 3)
            .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
            .collect();
        let (a, b) = tris.split_at(tris.len() / 2);
        let state = DrawState {
            cull: Cull::None,
            ..DrawState::opaque()
        };
        let draw_with = |shader: &Wavy| {
            let mut target = Target::new(W, H, Vec4::ZERO);
            let mut stats = Stats::default();
            let draws = [a, b, a].map(|t| Draw {
                id: if std::ptr::eq(t, b) { 1 } else { 0 },
                clip: &clip,
                varyings: &var,
                stride: 2,
                triangles: t,
                state,
            });
            draw(&mut target, &draws, shader, &mut stats);
            (target.resolve().color, stats)
        };
        let (packed, ps) = draw_with(&Wavy { pack: true });
        let (plain, us) = draw_with(&Wavy { pack: false });
        let bits = |c: &[Vec4]| -> Vec<[u32; 4]> {
            c.iter().map(|v| v.to_array().map(f32::to_bits)).collect()
        };
        let covered = plain.iter().filter(|c| c.w != 0.0).count();
        assert!(covered > (W * H / 2) as usize, "{covered} pixels covered");
        assert!(
            bits(&packed) == bits(&plain),
            "deferred and forward images differ"
        );
        // Every covered pixel once (no lane of this shader's alpha is 0 where drawn), where
        // the forward fill shaded every fragment that passed the depth test.
        assert_eq!(ps.pixels_shaded, covered as u64);
        assert!(us.pixels_shaded > ps.pixels_shaded * 5 / 4, "{ps:?} {us:?}");
        eprintln!(
            "{} pixels shaded in {} deferred calls; forward {} in {}",
            ps.pixels_shaded, ps.shader_calls, us.pixels_shaded, us.shader_calls
        );
        // Groups are aligned rows of eight pixels, filled with every visible fragment of
        // one draw and facing that lies in them (not compacted across rows): on these tiny
        // triangles 0.56 of their lanes are in use, against 0.38 when each triangle's rows
        // are shaded on their own (the forward run here).
        let lanes = ps.pixels_shaded as f64 / (8 * ps.shader_calls) as f64;
        assert!(lanes > 0.5, "lanes in use: {lanes}, {ps:?}");
        assert!(ps.shader_calls * 2 < us.shader_calls, "{ps:?} {us:?}");
    }

    /// `facing_varyings`: set-up keeps the front half of the varyings for a front-facing
    /// triangle and the back half for a back-facing one.
    #[test]
    fn facing_varyings_keep_the_side_shown() {
        struct Rgba;
        impl PixelShader for Rgba {
            fn pixel(&self, _: TriInfo, v: &[f32]) -> Option<Vec4> {
                assert_eq!(v.len(), 4);
                Some(Vec4::new(v[0], v[1], v[2], v[3]))
            }
        }
        let front = [1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0];
        let var: Vec<f32> = (0..3).flat_map(|_| front).collect();
        let ccw = [
            Vec4::new(-0.8, -0.8, 0.5, 1.0),
            Vec4::new(0.8, -0.8, 0.5, 1.0),
            Vec4::new(0.0, 0.8, 0.5, 1.0),
        ];
        for (tris, want) in [
            ([[0u32, 1, 2]], Vec4::X.with_w(1.0)),
            ([[0, 2, 1]], Vec4::Z.with_w(1.0)),
        ] {
            let mut target = Target::new(W, H, Vec4::ZERO);
            let d = Draw {
                id: 0,
                clip: &ccw,
                varyings: &var,
                stride: 8,
                triangles: &tris,
                state: DrawState {
                    cull: Cull::None,
                    facing_varyings: true,
                    ..DrawState::opaque()
                },
            };
            draw(&mut target, &[d], &PerPixel(Rgba), &mut Stats::default());
            let c = target.resolve().pixel(W / 2, H / 2);
            assert_eq!(c, want, "{tris:?}");
        }
    }
}
