//! Per-tile fill: the inner loop.
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
//!   Each row of a block is one eight-lane step: coverage mask from the exact integer edge
//!   values and depth first, for every row of the block; then, for each row with a live
//!   lane, interpolation and one call of the shader for the eight lanes (see [`block`] for
//!   why the two steps are apart). Per-triangle constants (edge steps, lane offsets, barycentric steps,
//!   derivative constants) are computed once per triangle and tile.
//! - Deferred shading: on small triangles most of a row's eight lanes are empty (24 % in
//!   use on the bunny at 1080p), the shader costs the same for one live lane as for eight,
//!   and a fragment drawn over later was shaded for nothing (a third of the fragments of
//!   the teapot and the cow at 1080p). For a shader that [defers](FragmentShader::packs) a
//!   draw (the lit shader, unless the draw is alpha-tested), on a single-sample tile with
//!   colour replaced, the fill only tests coverage and depth: it writes each passing
//!   fragment's depth at the test and keeps, per pixel, the triangle and the perspective
//!   weights of the last fragment that passed (a visibility buffer). The tile's visible
//!   fragments are shaded at its end, or before a triangle that is not deferred (it may
//!   blend with what is under it): eight pixels at a time where one triangle covers seven
//!   or eight of them, the others gathered lane by lane into batches of eight across rows
//!   and triangles of one draw and facing. Each pixel is shaded once, by the triangle that
//!   the forward order would have left there, with the same interpolation, so images are
//!   bit for bit those of shading every fragment in order.
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

// Lane and edge loops index several arrays by one counter on purpose: that shape vectorises.
#![allow(clippy::needless_range_loop)]

use super::framebuffer::{sample_offsets, sample_reach, Tile, TILE, TILE_PIXELS};
use super::pipeline::Chunk;
use super::pipeline::{Blend, DepthTest, DrawState};
use super::setup::{padded, SetupTri, ONE};
use super::{Colors, FragmentShader, Fragments, TriInfo, MAX_VARYINGS};
use crate::simd::kernel::edge_signs;
use crate::simd::lanes::{Kernel, F8, LANES, M8};

const BLOCK: u32 = 8;
const HALF: i64 = ONE / 2;
/// Samples per pixel of a multisampled tile.
const SAMPLES: usize = 4;

/// Fragment counters of one tile, and the lanes' working memory (kept from tile to tile by
/// each worker: zeroing it per row cost more than the interpolation it holds).
#[derive(Default)]
pub(crate) struct FillCounters {
    pub shaded: u64,
    pub depth_rejected: u64,
    pub calls: u64,
    /// The rows of the current block waiting to be shaded ([`block`]).
    pending: [Pending; BLOCK as usize],
    var: [F8; MAX_VARYINGS],
    ddx: [F8; MAX_VARYINGS],
    ddy: [F8; MAX_VARYINGS],
    /// Fragments gathered into batches of eight (deferred shading), one per draw and facing
    /// met lately.
    packs: [Pack; PACKS],
    /// The visibility buffer of deferred shading.
    defer: Deferred,
}

impl FillCounters {
    /// Ready for a new tile: counters zeroed (the visibility buffer is empty after every
    /// tile's last [`fill`]).
    pub(crate) fn begin_tile(&mut self) {
        self.shaded = 0;
        self.depth_rejected = 0;
        self.calls = 0;
        self.packs.iter_mut().for_each(|p| p.len = 0);
        self.defer.pending = false;
    }
}

/// Groups of eight pixels in a tile.
const GROUPS: usize = TILE_PIXELS / LANES;

/// The deferred fragments of a tile (see the module docs, "Deferred shading"): per pixel,
/// the last fragment of a deferred triangle that passed the depth test.
#[derive(Default)]
struct Deferred {
    /// Whether any group has a live lane.
    pending: bool,
    /// Per group of eight pixels (tile offset / 8): the lanes holding a fragment.
    live: Vec<u32>,
    /// Per pixel: its fragment's triangle ([`TriId`]), and the perspective weights `p_1`,
    /// `p_2` and `1 / D` there (meaningful where `live` says so).
    tri: Vec<u32>,
    p1: Vec<f32>,
    p2: Vec<f32>,
    inv: Vec<f32>,
}

impl Deferred {
    /// Keeps lanes `live` of the row at tile offset `o` (a multiple of eight), fragments of
    /// triangle `id` with perspective weights `p`, over what the row held.
    #[inline(always)]
    fn record(&mut self, o: usize, live: u32, id: u32, p: [F8; 3]) {
        if self.tri.len() < TILE_PIXELS {
            // Once per worker thread (see `pipeline::flush`).
            self.live = vec![0; GROUPS];
            self.tri = vec![0; TILE_PIXELS];
            self.p1 = vec![0.0; TILE_PIXELS];
            self.p2 = vec![0.0; TILE_PIXELS];
            self.inv = vec![0.0; TILE_PIXELS];
        }
        let m = M8::from_bits(live);
        for (plane, v) in [&mut self.p1, &mut self.p2, &mut self.inv]
            .into_iter()
            .zip(p)
        {
            let d = &mut plane[o..o + LANES];
            d.copy_from_slice(&F8::select(m, v, F8::load(d)).0);
        }
        let t = &mut self.tri[o..o + LANES];
        for i in 0..LANES {
            if live >> i & 1 != 0 {
                t[i] = id;
            }
        }
        self.live[o / LANES] |= live;
        self.pending = true;
    }

    /// The perspective weights of the group at tile offset `o`.
    #[inline(always)]
    fn weights(&self, o: usize) -> [F8; 3] {
        [
            F8::load(&self.p1[o..o + LANES]),
            F8::load(&self.p2[o..o + LANES]),
            F8::load(&self.inv[o..o + LANES]),
        ]
    }

    /// The lanes of `lanes` in the group at `o` whose fragment is triangle `id`'s.
    #[inline(always)]
    fn same(&self, o: usize, lanes: u32, id: u32) -> u32 {
        let t = &self.tri[o..o + LANES];
        let mut m = 0;
        for i in 0..LANES {
            m |= u32::from(t[i] == id) << i;
        }
        m & lanes
    }
}

/// A triangle of the tile's chunks: chunk index times 2^16 plus its index in the chunk
/// (a chunk holds at most [`CHUNK`](super::pipeline::CHUNK) = 2048 triangles).
pub(crate) type TriId = u32;

/// Triangle `id` of `chunks` and the varyings' array it indexes.
#[inline(always)]
fn triangle(chunks: &[Chunk], id: TriId) -> Option<(&SetupTri, &[f32])> {
    let c = chunks.get((id >> 16) as usize)?;
    Some((c.tris.get((id & 0xffff) as usize)?, &c.attrs[..]))
}

fn key(tri: &SetupTri, v: &Varyings<'_>) -> PackKey {
    PackKey {
        draw: tri.info.draw,
        front: tri.info.front,
        stride: v.stride,
        derivatives: v.grad.map_or(0, |g| g.1),
    }
}

/// Fragments of one draw and facing gathered into one batch of eight lanes (see the module
/// docs, "Deferred shading"). Lane `i` is the pixel at tile offset `o[i]`; its depth is
/// already written.
#[derive(Clone, Debug, Default)]
struct Pack {
    /// Lanes filled (the first `len`).
    len: usize,
    /// What the lanes share: the triangles' draw and facing, the varyings' count and the
    /// derivatives' count. Meaningful while `len > 0`.
    key: PackKey,
    o: [u32; LANES],
    var: [F8; MAX_VARYINGS],
    ddx: [F8; MAX_VARYINGS],
    ddy: [F8; MAX_VARYINGS],
}

/// Live lanes from which a group of deferred fragments of one triangle is shaded as it is.
const DIRECT_LANES: u32 = 7;

/// Packs filled at once: fragments of different draws or facings go to different packs
/// (the pixels of a tile alternate between them, e.g. at silhouettes).
const PACKS: usize = 4;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct PackKey {
    draw: u32,
    front: bool,
    stride: usize,
    derivatives: usize,
}

/// A triangle's varyings: vertex 0, differences to vertices 1 and 2 (each padded to a
/// multiple of 4), the number that are real, and the derivatives' constants if the shader
/// reads derivatives.
#[derive(Clone, Copy)]
struct Varyings<'a> {
    v0: &'a [f32],
    d1: &'a [f32],
    d2: &'a [f32],
    stride: usize,
    grad: Option<(usize, usize, Gradients)>,
}

/// What the rows of one triangle share, computed once per triangle and tile.
struct Rows<'a> {
    tri: &'a SetupTri,
    /// Edge steps per pixel along y, and per lane offsets along x (in i32 instead when
    /// `narrow`, see `fill`).
    step_y: [i64; 3],
    lane_x: [[i64; LANES]; 3],
    lane_x32: [[i32; LANES]; 3],
    narrow: bool,
    /// λ0, λ1, λ2 per pixel along x, as lane offsets.
    l0_lanes: F8,
    l1_lanes: F8,
    l2_lanes: F8,
    var: Varyings<'a>,
    /// The triangle's fragments are deferred (their depth is written at the test).
    defer: bool,
    id: TriId,
}

/// Per-triangle constants of a multisampled tile: each sample's offsets of the three edge
/// values and of the depth from those at the pixel centre.
struct Samples {
    edge: [[i64; 3]; SAMPLES],
    z: [F8; SAMPLES],
}

impl Samples {
    fn new(tri: &SetupTri) -> Self {
        // z = z0 + λ1 dz1 + λ2 dz2 with λ_k = E_k / area: per fixed unit along x,
        // dz/dx = (a_1 dz1 + a_2 dz2) / area; likewise along y with b.
        let dzdx = (tri.a[1] as f32 * tri.z[1] + tri.a[2] as f32 * tri.z[2]) * tri.inv_area;
        let dzdy = (tri.b[1] as f32 * tri.z[1] + tri.b[2] as f32 * tri.z[2]) * tri.inv_area;
        let mut out = Self {
            edge: [[0; 3]; SAMPLES],
            z: [F8::ZERO; SAMPLES],
        };
        for (s, o) in sample_offsets(SAMPLES as u32).iter().enumerate() {
            let (dx, dy) = (i64::from(o[0]) * (ONE / 16), i64::from(o[1]) * (ONE / 16));
            for k in 0..3 {
                let (a, b) = tri.ab(k);
                out.edge[s][k] = a * dx + b * dy;
            }
            out.z[s] = F8::splat(dzdx * dx as f32 + dzdy * dy as f32);
        }
        out
    }
}

/// Fills the part of `tri` that lies in `tile` (`.1` holds its varyings, `.2` is where it
/// lies in `chunks`); `None` after the tile's last triangle shades the deferred fragments.
///
/// Every shading of the tile happens at the one call of [`drain`] below (this function is
/// called from one place per kernel too): the shader is the largest code in the loop, and
/// each further call site would compile another copy of it.
#[inline(always)]
pub(crate) fn fill<K: Kernel, S: FragmentShader>(
    tile: &mut Tile,
    tri: Option<(&SetupTri, &[f32], TriId)>,
    chunks: &[Chunk],
    shader: &S,
    n: &mut FillCounters,
) {
    let rows = tri.and_then(|(tri, attrs, id)| rows::<S>(tile, tri, attrs, id, shader));
    // The deferred fragments are shaded at the end, and before a triangle that is not
    // deferred (a triangle with no pixel here changes nothing).
    let mut resolve = n.defer.pending && (tri.is_none() || rows.as_ref().is_some_and(|r| !r.defer));
    // The triangle's bounds in the tile (empty without one).
    let (x0, y0, x1, y1) = rows.as_ref().map_or((0, 0, 0, 0), |r| {
        let t = r.tri;
        (
            t.x0.max(tile.x0),
            t.y0.max(tile.y0),
            t.x1.min(tile.x0 + tile.w - 1),
            t.y1.min(tile.y0 + tile.h - 1),
        )
    });
    let multi = rows
        .as_ref()
        .filter(|_| tile.samples() as usize == SAMPLES)
        .map(|r| Samples::new(r.tri));
    let reach = sample_reach(tile.samples());
    let first_bx = x0 - x0.saturating_sub(tile.x0) % BLOCK;
    let mut by = y0 - y0.saturating_sub(tile.y0) % BLOCK;
    let mut bx = first_bx;
    loop {
        let (count, at) = if resolve {
            (0, 0)
        } else {
            let Some(r) = rows.as_ref() else {
                break;
            };
            if by > y1 {
                break;
            }
            let at = bx;
            let (sx0, sy0) = (bx.max(x0), by.max(y0));
            let (sx1, sy1) = ((bx + BLOCK - 1).min(x1), (by + BLOCK - 1).min(y1));
            bx += BLOCK;
            if bx > x1 {
                bx = first_bx;
                by += BLOCK;
            }
            // Lanes of the block inside the triangle's (tile-clipped) bounds.
            let span = ((1u32 << (sx1 - at + 1)) - 1) & !((1u32 << (sx0 - at)) - 1);
            let cov = classify(r.tri, reach, sx0, sy0, sx1, sy1);
            let count = match (&multi, cov) {
                (_, Coverage::None) => 0,
                (None, Coverage::Full) => block::<K, false>(tile, r, n, at, sy0, sy1, span),
                (None, Coverage::Partial) => block::<K, true>(tile, r, n, at, sy0, sy1, span),
                (Some(m), Coverage::Full) => {
                    block_ms::<K, false>(tile, r, m, n, at, sy0, sy1, span)
                }
                (Some(m), Coverage::Partial) => {
                    block_ms::<K, true>(tile, r, m, n, at, sy0, sy1, span)
                }
            };
            if count == 0 {
                continue;
            }
            (count, at)
        };
        drain::<K, S>(
            tile,
            rows.as_ref(),
            multi.as_ref(),
            count,
            resolve.then_some(chunks),
            shader,
            n,
            at,
        );
        resolve = false;
    }
}

/// The per-triangle constants of `tri`'s rows in `tile`, or `None` if it has no pixel there
/// or its varyings are missing.
#[inline(always)]
fn rows<'a, S: FragmentShader>(
    tile: &Tile,
    tri: &'a SetupTri,
    attrs: &'a [f32],
    id: TriId,
    shader: &S,
) -> Option<Rows<'a>> {
    let x0 = tri.x0.max(tile.x0);
    let y0 = tri.y0.max(tile.y0);
    let x1 = tri.x1.min(tile.x0 + tile.w - 1);
    let y1 = tri.y1.min(tile.y0 + tile.h - 1);
    if x0 > x1 || y0 > y1 {
        return None;
    }
    let var = varyings(tri, attrs, shader)?;
    let step_x = [0, 1, 2].map(|k| tri.ab(k).0 * ONE);
    let step_y = [0, 1, 2].map(|k| tri.ab(k).1 * ONE);
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
    let defer = tile.samples() == 1
        && st.color_write
        && st.blend == Blend::Replace
        && shader.packs(tri.info.draw);
    Some(Rows {
        tri,
        step_y,
        lane_x,
        lane_x32,
        narrow,
        l0_lanes: F8::RAMP * (step_x[0] as f32 * tri.inv_area),
        l1_lanes: F8::RAMP * (step_x[1] as f32 * tri.inv_area),
        l2_lanes: F8::RAMP * (step_x[2] as f32 * tri.inv_area),
        var,
        defer,
        id,
    })
}

/// `tri`'s varyings in `attrs`, with the derivatives' constants if the shader reads
/// derivatives of its draw; `None` if they are missing.
#[inline(always)]
fn varyings<'a, S: FragmentShader>(
    tri: &SetupTri,
    attrs: &'a [f32],
    shader: &S,
) -> Option<Varyings<'a>> {
    let stride = tri.stride as usize;
    let row = padded(stride);
    let at = tri.attr as usize;
    let var = attrs.get(at..at + 3 * row)?;
    let grad = shader
        .derivatives(tri.info.draw)
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

/// A row of a block whose coverage and depth tests passed, waiting to be shaded.
#[derive(Clone, Copy, Debug)]
struct Pending {
    y: u32,
    /// Offset of the row's first pixel in the tile.
    o: usize,
    /// Lanes that passed on any sample (the lanes to shade).
    live: u32,
    /// Lanes that passed per sample (only `pass[0]` on a single-sample tile).
    pass: [u32; SAMPLES],
    /// Screen-space barycentrics at the pixel centres.
    l: [F8; 3],
    /// Depth at the pixel centres.
    z: F8,
}

impl Pending {
    const EMPTY: Pending = Pending {
        y: 0,
        o: 0,
        live: 0,
        pass: [0; SAMPLES],
        l: [F8::ZERO; 3],
        z: F8::ZERO,
    };
}

impl Default for Pending {
    fn default() -> Self {
        Pending::EMPTY
    }
}

/// Coverage and early depth of rows `y0..=y1` of the 8-pixel-wide block at `bx` (lanes
/// outside `span` are off): the rows with a live lane go to `n.pending` (kept with the
/// tile's counters: a fresh array per triangle cost a 1.4 KB clear), and their count is
/// returned; a deferred triangle's live lanes go to the visibility buffer instead.
///
/// Tests and shading are separate steps so that the shader, by far the largest code in the
/// loop, is inlined once per kernel ([`drain`]) and not once per coverage case: with
/// the glTF PBR shader, four copies tripled the release build time. Deferring the shading
/// to the end of the block changes nothing: a block's rows are distinct pixels.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn block<K: Kernel, const TEST: bool>(
    tile: &mut Tile,
    r: &Rows<'_>,
    n: &mut FillCounters,
    bx: u32,
    y0: u32,
    y1: u32,
    span: u32,
) -> usize {
    let tri = r.tri;
    let st = tri.state;
    let mut row = [
        edge_at(tri, 0, bx, y0),
        edge_at(tri, 1, bx, y0),
        edge_at(tri, 2, bx, y0),
    ];
    let (z0, z1, z2) = (
        F8::splat(tri.z[0]),
        F8::splat(tri.z[1]),
        F8::splat(tri.z[2]),
    );
    let mut count = 0;
    for y in y0..=y1 {
        let mut cover = span;
        if TEST {
            cover &= row_mask(r, row);
        }
        let o = ((y - tile.y0) * TILE + (bx - tile.x0)) as usize;
        if cover != 0 {
            let l = barycentrics(r, row);
            let z = K::fma(z2, l[2], K::fma(z1, l[1], z0));
            let pass = depth_pass(st.depth_test, z, &tile.depth[o..o + LANES]);
            let live = cover & pass;
            n.depth_rejected += u64::from((cover & !pass).count_ones());
            if live != 0 && r.defer {
                if st.depth_write {
                    // A deferred fragment is shaded later, maybe after other triangles:
                    // they must test against its depth now.
                    let d = &mut tile.depth[o..o + LANES];
                    d.copy_from_slice(&F8::select(M8::from_bits(live), z, F8::load(d)).0);
                }
                n.defer.record(o, live, r.id, perspective::<K>(tri, l));
            } else if live != 0 {
                let mut passes = [0; SAMPLES];
                passes[0] = live;
                n.pending[count] = Pending {
                    y,
                    o,
                    live,
                    pass: passes,
                    l,
                    z,
                };
                count += 1;
            }
        }
        for k in 0..3 {
            row[k] += r.step_y[k];
        }
    }
    count
}

/// [`block`] on a multisampled tile: coverage and depth per sample (`m`); [`shade_block`]
/// then calls the shader once per row at the pixel centres and writes its colour to the
/// samples that passed.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn block_ms<K: Kernel, const TEST: bool>(
    tile: &Tile,
    r: &Rows<'_>,
    m: &Samples,
    n: &mut FillCounters,
    bx: u32,
    y0: u32,
    y1: u32,
    span: u32,
) -> usize {
    let tri = r.tri;
    let st = tri.state;
    let mut row = [
        edge_at(tri, 0, bx, y0),
        edge_at(tri, 1, bx, y0),
        edge_at(tri, 2, bx, y0),
    ];
    let (z0, z1, z2) = (
        F8::splat(tri.z[0]),
        F8::splat(tri.z[1]),
        F8::splat(tri.z[2]),
    );
    let mut count = 0;
    for y in y0..=y1 {
        let mut cover = [span; SAMPLES];
        if TEST {
            for (c, e) in cover.iter_mut().zip(&m.edge) {
                *c &= row_mask(r, [row[0] + e[0], row[1] + e[1], row[2] + e[2]]);
            }
        }
        let any = cover.iter().fold(0, |a, c| a | c);
        let o = ((y - tile.y0) * TILE + (bx - tile.x0)) as usize;
        if any != 0 {
            let l = barycentrics(r, row);
            let zc = K::fma(z2, l[2], K::fma(z1, l[1], z0));
            let mut pass = [0u32; SAMPLES];
            for s in 0..SAMPLES {
                let d = &tile.depth[s * TILE_PIXELS + o..][..LANES];
                pass[s] = cover[s] & depth_pass(st.depth_test, zc + m.z[s], d);
            }
            let live = pass.iter().fold(0, |a, p| a | p);
            n.depth_rejected += u64::from((any & !live).count_ones());
            if live != 0 {
                n.pending[count] = Pending {
                    y,
                    o,
                    live,
                    pass,
                    l,
                    z: zc,
                };
                count += 1;
            }
        }
        for k in 0..3 {
            row[k] += r.step_y[k];
        }
    }
    count
}

/// What [`drain`] shades next.
#[derive(Clone, Copy)]
enum Job {
    /// A pending row of the current triangle.
    Row(Pending),
    /// Deferred fragments of the triangle last looked up in lanes `mask` of the group at
    /// tile offset `o`.
    Group { o: usize, mask: u32 },
    /// Pack `.0`.
    Pack(usize),
}

/// Shades the first `count` pending rows of the block at `bx` and writes what the shader
/// keeps: to the one sample of a plain tile, or to the samples that passed of a
/// multisampled one (`m`). With `resolve` (the tile's triangles; `count` is 0 then),
/// shades the deferred fragments instead: groups of eight pixels mostly of one triangle as
/// they are, the rest gathered into packs of eight lanes.
///
/// The one place the shader is called (see [`fill`]).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn drain<K: Kernel, S: FragmentShader>(
    tile: &mut Tile,
    r: Option<&Rows<'_>>,
    m: Option<&Samples>,
    count: usize,
    resolve: Option<&[Chunk]>,
    shader: &S,
    n: &mut FillCounters,
    bx: u32,
) {
    // Next pending row, or next group of the visibility buffer.
    let mut next = 0;
    // Resolving: the group being read, its lanes not yet taken, and the lanes of the
    // triangle interpolated last (`n.var`) still to copy into the pack.
    let (mut group, mut rest) = (0, 0u32);
    let (mut copy, mut copy_key) = (0u32, PackKey::default());
    // The triangle of the last deferred fragments looked up.
    let mut cur = None;
    loop {
        let job = if let Some(chunks) = resolve {
            let mut job = None;
            while job.is_none() {
                if copy != 0 {
                    let packs = &mut n.packs;
                    let slot = (packs.iter().position(|p| p.len > 0 && p.key == copy_key))
                        .or_else(|| packs.iter().position(|p| p.len == 0));
                    let Some(slot) = slot else {
                        // Every pack holds another draw or facing: shade the fullest.
                        let i = (0..PACKS).max_by_key(|&i| packs[i].len).unwrap_or(0);
                        job = Some(Job::Pack(i));
                        break;
                    };
                    let p = &mut packs[slot];
                    p.key = copy_key;
                    let o = group * LANES;
                    while copy != 0 && p.len < LANES {
                        let i = copy.trailing_zeros() as usize;
                        copy &= copy - 1;
                        let k = p.len;
                        p.len += 1;
                        p.o[k] = (o + i) as u32;
                        for j in 0..copy_key.stride {
                            p.var[j].0[k] = n.var[j].0[i];
                        }
                        for j in 0..copy_key.derivatives {
                            p.ddx[j].0[k] = n.ddx[j].0[i];
                            p.ddy[j].0[k] = n.ddy[j].0[i];
                        }
                    }
                    if p.len == LANES {
                        job = Some(Job::Pack(slot));
                    }
                    continue;
                }
                if rest == 0 {
                    let d = &mut n.defer;
                    while next < GROUPS && d.live[next] == 0 {
                        next += 1;
                    }
                    if next == GROUPS {
                        if let Some(i) = n.packs.iter().position(|p| p.len > 0) {
                            job = Some(Job::Pack(i));
                            break;
                        }
                        d.pending = false;
                        return;
                    }
                    group = next;
                    rest = std::mem::take(&mut d.live[group]);
                    next += 1;
                    n.shaded += u64::from(rest.count_ones());
                }
                let o = group * LANES;
                let FillCounters {
                    var,
                    ddx,
                    ddy,
                    defer: d,
                    ..
                } = &mut *n;
                let id = d.tri[o + rest.trailing_zeros() as usize];
                let mask = d.same(o, rest, id);
                rest &= !mask;
                if cur
                    .as_ref()
                    .is_none_or(|c: &(TriId, &SetupTri, Varyings<'_>)| c.0 != id)
                {
                    cur = triangle(chunks, id)
                        .and_then(|(tri, attrs)| Some((id, tri, varyings(tri, attrs, shader)?)));
                }
                // (Every recorded triangle has its varyings: `rows` checked.)
                let Some((_, tri, v)) = &cur else {
                    continue;
                };
                interpolate::<K>(v, d.weights(o), var, ddx, ddy);
                if mask.count_ones() >= DIRECT_LANES {
                    job = Some(Job::Group { o, mask });
                } else {
                    (copy, copy_key) = (mask, key(tri, v));
                }
            }
            job
        } else {
            let Some(r) = r else {
                return;
            };
            if next == count {
                return;
            }
            let row = n.pending[next];
            next += 1;
            n.shaded += u64::from(row.live.count_ones());
            let FillCounters { var, ddx, ddy, .. } = &mut *n;
            interpolate::<K>(&r.var, perspective::<K>(r.tri, row.l), var, ddx, ddy);
            Some(Job::Row(row))
        };
        let Some(job) = job else {
            return;
        };
        n.calls += 1;
        let mut out = Colors::default();
        let keep = {
            let frag = match job {
                Job::Pack(i) => {
                    let p = &n.packs[i];
                    Fragments {
                        tri: TriInfo {
                            draw: p.key.draw,
                            front: p.key.front,
                        },
                        x: 0,
                        y: 0,
                        mask: (1u32 << p.len) - 1,
                        var: &p.var[..p.key.stride],
                        ddx: &p.ddx[..p.key.derivatives],
                        ddy: &p.ddy[..p.key.derivatives],
                    }
                }
                Job::Group { o, mask } => {
                    let Some((_, tri, v)) = &cur else {
                        return;
                    };
                    let nd = v.grad.map_or(0, |g| g.1);
                    Fragments {
                        tri: tri.info,
                        x: tile.x0 + (o as u32 % TILE),
                        y: tile.y0 + o as u32 / TILE,
                        mask,
                        var: &n.var[..v.stride],
                        ddx: &n.ddx[..nd],
                        ddy: &n.ddy[..nd],
                    }
                }
                Job::Row(row) => {
                    let Some(r) = r else {
                        return;
                    };
                    let nd = r.var.grad.map_or(0, |g| g.1);
                    Fragments {
                        tri: r.tri.info,
                        x: bx,
                        y: row.y,
                        mask: row.live,
                        var: &n.var[..r.var.stride],
                        ddx: &n.ddx[..nd],
                        ddy: &n.ddy[..nd],
                    }
                }
            };
            shader.shade::<K>(&frag, &mut out) & frag.mask
        };
        match job {
            Job::Pack(i) => {
                scatter(tile, &n.packs[i], keep, &out);
                n.packs[i].len = 0;
            }
            Job::Group { o, .. } => {
                let Some((_, tri, _)) = &cur else {
                    return;
                };
                // The depth is written: colour only.
                let st = DrawState {
                    depth_write: false,
                    ..tri.state
                };
                if keep != 0 {
                    write::<K>(tile, st, 0, o, keep, &out, F8::ZERO);
                }
            }
            Job::Row(row) => {
                let Some(st) = r.map(|r| r.tri.state) else {
                    return;
                };
                if keep == 0 {
                    continue;
                }
                match m {
                    None => write::<K>(tile, st, 0, row.o, keep, &out, row.z),
                    Some(m) => {
                        for s in 0..SAMPLES {
                            if keep & row.pass[s] != 0 {
                                let z = row.z + m.z[s];
                                write::<K>(tile, st, s, row.o, keep & row.pass[s], &out, z);
                            }
                        }
                    }
                }
            }
        }
    }
}

/// Writes the colours of a shaded pack to its lanes' pixels (their depth is written).
#[inline(always)]
fn scatter(tile: &mut Tile, p: &Pack, keep: u32, out: &Colors) {
    let (color, _) = tile.planes_mut();
    let (cr, rest) = color.split_at_mut(TILE_PIXELS);
    let (cg, rest) = rest.split_at_mut(TILE_PIXELS);
    let (cb, rest) = rest.split_at_mut(TILE_PIXELS);
    let ca = &mut rest[..TILE_PIXELS];
    for k in 0..p.len {
        if keep & (1 << k) == 0 {
            continue;
        }
        let o = p.o[k] as usize;
        if o < TILE_PIXELS {
            cr[o] = out.r.0[k];
            cg[o] = out.g.0[k];
            cb[o] = out.b.0[k];
            ca[o] = out.a.0[k];
        }
    }
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
    let mut v = [0u32; LANES];
    for i in 0..LANES {
        let w = (row[0] + r.lane_x[0][i]) | (row[1] + r.lane_x[1][i]) | (row[2] + r.lane_x[2][i]);
        // The high half carries the sign.
        v[i] = ((w as u64) >> 32) as u32;
    }
    !M8(v).bits()
}

/// Screen-space barycentrics of a row's lanes from its biased edge values at lane 0: the
/// unbiased values, each λ from its own exact edge value (1 - λ1 - λ2 cancels near vertex 0).
#[inline(always)]
fn barycentrics(r: &Rows<'_>, row: [i64; 3]) -> [F8; 3] {
    let (tri, inv) = (r.tri, r.tri.inv_area);
    [
        F8::splat((row[0] - tri.bias(0)) as f32 * inv) + r.l0_lanes,
        F8::splat((row[1] - tri.bias(1)) as f32 * inv) + r.l1_lanes,
        F8::splat((row[2] - tri.bias(2)) as f32 * inv) + r.l2_lanes,
    ]
}

/// Lanes where depth `z` passes `test` against the stored `depth` (eight values).
#[inline(always)]
fn depth_pass(test: DepthTest, z: F8, depth: &[f32]) -> u32 {
    let depth = F8::load(depth);
    match test {
        DepthTest::Greater => z.gt(depth).bits(),
        DepthTest::GreaterEqual => z.ge(depth).bits(),
        DepthTest::Always => u32::MAX,
    }
}

/// The perspective weights `[p_1, p_2, 1 / D]` of `tri` at screen-space barycentrics `l`.
#[inline(always)]
fn perspective<K: Kernel>(tri: &SetupTri, l: [F8; 3]) -> [F8; 3] {
    // Perspective weights p_k = λ_k (1/w_k) / Σ λ_j (1/w_j). Inside the triangle every λ is
    // >= 0 (clamped against rounding), so every term of D is >= 0: no cancellation, and D > 0
    // even where one 1/w is tiny (a vertex at w = 1e30).
    let (l0, l1, l2) = (l[0].max(F8::ZERO), l[1].max(F8::ZERO), l[2].max(F8::ZERO));
    let w1 = l1 * tri.iw[1];
    let w2 = l2 * tri.iw[2];
    let d = K::fma(l0, F8::splat(tri.iw[0]), w1 + w2);
    let inv_d = d.recip();
    [w1 * inv_d, w2 * inv_d, inv_d]
}

/// Interpolates a triangle's varyings `v` (and their derivatives, if the draw asks) at
/// perspective weights `p` ([`perspective`]) into `var` (and `ddx`, `ddy`).
#[inline(always)]
fn interpolate<K: Kernel>(
    v: &Varyings<'_>,
    p: [F8; 3],
    var: &mut [F8; MAX_VARYINGS],
    ddx: &mut [F8; MAX_VARYINGS],
    ddy: &mut [F8; MAX_VARYINGS],
) {
    let [p1, p2, inv_d] = p;
    // Groups of four (the rows are padded): a fixed inner trip count the compiler unrolls.
    for (((out, v0), d1), d2) in var
        .chunks_exact_mut(4)
        .zip(v.v0.chunks_exact(4))
        .zip(v.d1.chunks_exact(4))
        .zip(v.d2.chunks_exact(4))
    {
        for j in 0..4 {
            out[j] = K::fma(
                F8::splat(d2[j]),
                p2,
                K::fma(F8::splat(d1[j]), p1, F8::splat(v0[j])),
            );
        }
    }
    if let Some((first, count, g)) = &v.grad {
        let [d1x, d2x, d1y, d2y] = g.weights::<K>(p1, p2, inv_d);
        for j in 0..*count {
            let (a, b) = (F8::splat(v.d1[first + j]), F8::splat(v.d2[first + j]));
            ddx[j] = K::fma(a, d1x, b * d2x);
            ddy[j] = K::fma(a, d1y, b * d2y);
        }
    }
}

/// Writes colour `out` and depth `z` to the `keep` lanes of sample `s` at offset `o`, as the
/// draw state says (blend, colour and depth writes).
#[inline(always)]
fn write<K: Kernel>(
    tile: &mut Tile,
    st: DrawState,
    s: usize,
    o: usize,
    keep: u32,
    out: &Colors,
    z: F8,
) {
    let keep_m = M8::from_bits(keep);
    let full = keep & 0xFF == 0xFF;
    let (color, depth) = tile.planes_mut();
    if st.color_write {
        let color = &mut color[4 * s * TILE_PIXELS..];
        let (cr, rest) = color.split_at_mut(TILE_PIXELS);
        let (cg, rest) = rest.split_at_mut(TILE_PIXELS);
        let (cb, rest) = rest.split_at_mut(TILE_PIXELS);
        let ca = &mut rest[..TILE_PIXELS];
        let (pr, pg, pb, pa) = (
            &mut cr[o..o + LANES],
            &mut cg[o..o + LANES],
            &mut cb[o..o + LANES],
            &mut ca[o..o + LANES],
        );
        if full && st.blend == Blend::Replace {
            // Every lane replaced: no need to read what was there.
            pr.copy_from_slice(&out.r.0);
            pg.copy_from_slice(&out.g.0);
            pb.copy_from_slice(&out.b.0);
            pa.copy_from_slice(&out.a.0);
        } else {
            blend::<K>(st.blend, keep_m, out, [pr, pg, pb, pa]);
        }
    }
    if st.depth_write {
        let depth = &mut depth[s * TILE_PIXELS + o..][..LANES];
        let v = if full {
            z
        } else {
            F8::select(keep_m, z, F8::load(depth))
        };
        depth.copy_from_slice(&v.0);
    }
}

/// Blends `out` into the eight pixels of the four colour planes `dst` where `keep` is set.
#[inline(always)]
fn blend<K: Kernel>(mode: Blend, keep: M8, out: &Colors, dst: [&mut [f32]; 4]) {
    let [pr, pg, pb, pa] = dst;
    let (dr, dg, db, da) = (F8::load(pr), F8::load(pg), F8::load(pb), F8::load(pa));
    let (r2, g2, b2, a2) = match mode {
        Blend::Replace => (out.r, out.g, out.b, out.a),
        Blend::Alpha => {
            let a = out.a.clamp(0.0, 1.0);
            let na = F8::ONE - a;
            (
                K::fma(out.r, a, dr * na),
                K::fma(out.g, a, dg * na),
                K::fma(out.b, a, db * na),
                K::fma(da, na, a),
            )
        }
        Blend::Add => (out.r + dr, out.g + dg, out.b + db, out.a + da),
    };
    pr.copy_from_slice(&F8::select(keep, r2, dr).0);
    pg.copy_from_slice(&F8::select(keep, g2, dg).0);
    pb.copy_from_slice(&F8::select(keep, b2, db).0);
    pa.copy_from_slice(&F8::select(keep, a2, da).0);
}

/// Per-triangle constants of the perspective weights' derivatives (see the module docs).
#[derive(Clone, Copy, Default)]
struct Gradients {
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
    fn weights<K: Kernel>(&self, p1: F8, p2: F8, inv: F8) -> [F8; 4] {
        let f = |c: f32, p: F8, d: f32| K::fma(p, F8::splat(-d), F8::splat(c)) * inv;
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

    use crate::simd::{Kernel, F8};
    use crate::{
        draw, Colors, Cull, Draw, DrawState, FragmentShader, Fragments, PerPixel, PixelShader,
        Stats, Target, TriInfo,
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
        #[inline(always)]
        fn shade<K: Kernel>(&self, f: &Fragments<'_>, out: &mut Colors) -> u32 {
            assert_eq!((f.ddx.len(), f.ddy.len()), (2, 2));
            *out = Colors {
                r: f.ddx[0],
                g: f.ddx[1],
                b: f.ddy[0],
                a: f.ddy[1],
            };
            f.mask
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
        fn packs(&self, _: u32) -> bool {
            self.pack
        }
        #[inline(always)]
        fn shade<K: Kernel>(&self, f: &Fragments<'_>, out: &mut Colors) -> u32 {
            let (u, v) = (f.var[0], f.var[1]);
            let side = if f.tri.front { 1.0 } else { 0.5 };
            *out = Colors {
                r: (u * F8::splat(7.0) + v).map(f32::sin),
                g: (f.ddx[0] * F8::splat(31.0)).map(f32::cos) * side,
                b: f.ddy[1] * F8::splat(13.0) + F8::splat(f.tri.draw as f32),
                a: (u * v).sqrt(),
            };
            f.mask
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
        let lanes = ps.pixels_shaded as f64 / (8 * ps.shader_calls) as f64;
        assert!(lanes > 0.6, "packed lanes in use: {lanes}, {ps:?}");
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
