//! Per-tile fill: the inner loop.
//!
//! - Sample positions: pixel centres, (x + 0.5, y + 0.5) in pixels, i.e. `x * 256 + 128` in
//!   fixed point ([`SUBPIXEL_BITS`](super::SUBPIXEL_BITS) = 8 sub-pixel bits).
//! - Fill rule: top-left (see `setup`), so a pixel on an edge shared by two triangles is
//!   filled by exactly one of them.
//! - The tile is walked in 8x8 blocks. A block is skipped when one edge is negative at all
//!   its sample points, and filled without edge tests when all three edges are non-negative
//!   at all of them (edge functions are linear, so the extremes lie at block corners).
//! - Depth: early test before shading, reversed-Z, `z` interpolated linearly in screen space
//!   (z/w is affine there). Attributes are interpolated perspective-correctly:
//!   `p_k = λ_k (1/w_k) / Σ λ_j (1/w_j)` with screen-space barycentrics `λ_k = E_k / area`,
//!   then `V = V_0 + p_1 (V_1 - V_0) + p_2 (V_2 - V_0)`.

use glam::Vec4;

use super::framebuffer::{Tile, TILE};
use super::pipeline::{Blend, DepthTest};
use super::setup::{SetupTri, ONE};
use super::{FragmentShader, Varying};

const BLOCK: u32 = 8;
const HALF: i64 = ONE / 2;

/// Fragment counters of one tile.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct FillCounters {
    pub shaded: u64,
    pub depth_rejected: u64,
}

/// Fills the part of `tri` that lies in `tile`.
pub(crate) fn fill<S: FragmentShader>(
    tile: &mut Tile,
    tri: &SetupTri<S::Varying>,
    shader: &S,
    n: &mut FillCounters,
) {
    let x0 = tri.x0.max(tile.x0);
    let y0 = tri.y0.max(tile.y0);
    let x1 = tri.x1.min(tile.x0 + tile.w - 1);
    let y1 = tri.y1.min(tile.y0 + tile.h - 1);
    if x0 > x1 || y0 > y1 {
        return;
    }
    let mut by = y0 - (y0 - tile.y0) % BLOCK;
    while by <= y1 {
        let mut bx = x0 - (x0 - tile.x0) % BLOCK;
        while bx <= x1 {
            let (sx0, sy0) = (bx.max(x0), by.max(y0));
            let (sx1, sy1) = ((bx + BLOCK - 1).min(x1), (by + BLOCK - 1).min(y1));
            match classify(tri, sx0, sy0, sx1, sy1) {
                Coverage::None => {}
                Coverage::Full => span::<S, false>(tile, tri, shader, n, sx0, sy0, sx1, sy1),
                Coverage::Partial => span::<S, true>(tile, tri, shader, n, sx0, sy0, sx1, sy1),
            }
            bx += BLOCK;
        }
        by += BLOCK;
    }
}

enum Coverage {
    None,
    Partial,
    Full,
}

/// Edge function (biased) at the centre of pixel (x, y).
#[inline(always)]
fn edge_at<V>(tri: &SetupTri<V>, k: usize, x: u32, y: u32) -> i64 {
    tri.a[k] * (i64::from(x) * ONE + HALF)
        + tri.b[k] * (i64::from(y) * ONE + HALF)
        + tri.c[k]
        + tri.bias[k]
}

fn classify<V>(tri: &SetupTri<V>, x0: u32, y0: u32, x1: u32, y1: u32) -> Coverage {
    let mut full = true;
    let (dx, dy) = (i64::from(x1 - x0) * ONE, i64::from(y1 - y0) * ONE);
    for k in 0..3 {
        let e = edge_at(tri, k, x0, y0);
        let (ax, by) = (tri.a[k] * dx, tri.b[k] * dy);
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

#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn span<S: FragmentShader, const TEST: bool>(
    tile: &mut Tile,
    tri: &SetupTri<S::Varying>,
    shader: &S,
    n: &mut FillCounters,
    x0: u32,
    y0: u32,
    x1: u32,
    y1: u32,
) {
    let step_x = [tri.a[0] * ONE, tri.a[1] * ONE, tri.a[2] * ONE];
    let step_y = [tri.b[0] * ONE, tri.b[1] * ONE, tri.b[2] * ONE];
    let mut row = [
        edge_at(tri, 0, x0, y0),
        edge_at(tri, 1, x0, y0),
        edge_at(tri, 2, x0, y0),
    ];
    let st = tri.state;
    for y in y0..=y1 {
        let mut e = row;
        let base = ((y - tile.y0) * TILE) as usize;
        for x in x0..=x1 {
            if !TEST || (e[0] | e[1] | e[2]) >= 0 {
                // Unbiased edge values -> screen-space barycentrics.
                let l1 = (e[1] - tri.bias[1]) as f32 * tri.inv_area;
                let l2 = (e[2] - tri.bias[2]) as f32 * tri.inv_area;
                let z = tri.z[0] + tri.z[1] * l1 + tri.z[2] * l2;
                let o = base + (x - tile.x0) as usize;
                let pass = match st.depth_test {
                    DepthTest::Greater => z > tile.depth[o],
                    DepthTest::GreaterEqual => z >= tile.depth[o],
                    DepthTest::Always => true,
                };
                if pass {
                    let w1 = l1 * tri.iw[1];
                    let w2 = l2 * tri.iw[2];
                    let inv = 1.0 / ((1.0 - l1 - l2) * tri.iw[0] + w1 + w2);
                    let v = tri.var[0].mad2(&tri.var[1], w1 * inv, &tri.var[2], w2 * inv);
                    n.shaded += 1;
                    if let Some(c) = shader.fragment(tri.info, &v) {
                        if st.color_write {
                            tile.color[o] = blend(st.blend, c, tile.color[o]);
                        }
                        if st.depth_write {
                            tile.depth[o] = z;
                        }
                    }
                } else {
                    n.depth_rejected += 1;
                }
            }
            for k in 0..3 {
                e[k] += step_x[k];
            }
        }
        for k in 0..3 {
            row[k] += step_y[k];
        }
    }
}

#[inline(always)]
fn blend(mode: Blend, src: Vec4, dst: Vec4) -> Vec4 {
    match mode {
        Blend::Replace => src,
        Blend::Alpha => {
            let a = src.w.clamp(0.0, 1.0);
            (src * a + dst * (1.0 - a))
                .truncate()
                .extend(a + dst.w * (1.0 - a))
        }
        Blend::Add => src + dst,
    }
}
