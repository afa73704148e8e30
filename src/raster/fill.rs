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
//! - Derivatives (shaders with [`FragmentShader::DERIVATIVES`]): exact, analytic, at the pixel
//!   centre, not differences over 2x2 quads. The `λ_k` are affine in screen space with
//!   per-pixel steps `∂λ_k/∂x = a_k ONE / area`, `∂λ_k/∂y = b_k ONE / area`; with
//!   `D = Σ λ_j (1/w_j)` (so `∂D/∂x = Σ ∂λ_j/∂x (1/w_j)`, constant over the triangle),
//!   `∂p_k/∂x = (1/w_k)(∂λ_k/∂x D - λ_k ∂D/∂x) / D² = (∂λ_k/∂x (1/w_k) - p_k ∂D/∂x) / D`,
//!   and `∂V/∂x = ∂p_1/∂x (V_1 - V_0) + ∂p_2/∂x (V_2 - V_0)`; likewise for y. A piece of a
//!   clipped triangle carries its own vertices' 1/w and varyings (interpolated in clip
//!   space), so this is the derivative of the original triangle's varying there too.

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
    let grad = if S::DERIVATIVES {
        Gradients::new(tri)
    } else {
        Gradients::default()
    };
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
                    let (p1, p2) = (w1 * inv, w2 * inv);
                    let v = tri.var[0].mad2(&tri.var[1], p1, &tri.var[2], p2);
                    n.shaded += 1;
                    let shaded = if S::DERIVATIVES {
                        let [d1x, d2x, d1y, d2y] = grad.weights(p1, p2, inv);
                        let dvdx = S::Varying::combine2(&tri.var[1], d1x, &tri.var[2], d2x);
                        let dvdy = S::Varying::combine2(&tri.var[1], d1y, &tri.var[2], d2y);
                        shader.fragment_grad(tri.info, &v, &dvdx, &dvdy)
                    } else {
                        shader.fragment(tri.info, &v)
                    };
                    if let Some(c) = shaded {
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
    fn new<V>(tri: &SetupTri<V>) -> Self {
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

    /// `[∂p_1/∂x, ∂p_2/∂x, ∂p_1/∂y, ∂p_2/∂y]` at a pixel with perspective weights `p1`, `p2`
    /// and `inv = 1 / D`.
    #[inline(always)]
    fn weights(&self, p1: f32, p2: f32, inv: f32) -> [f32; 4] {
        [
            (self.cx[0] - p1 * self.dx) * inv,
            (self.cx[1] - p2 * self.dx) * inv,
            (self.cy[0] - p1 * self.dy) * inv,
            (self.cy[1] - p2 * self.dy) * inv,
        ]
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

#[cfg(test)]
mod tests {
    use glam::{Mat4, Vec2, Vec3, Vec4};

    use crate::raster::{draw, Cull, Draw, DrawState, FragmentShader, Stats, Target, TriInfo};
    use crate::scene::Camera;

    /// Outputs the interpolated varying (alpha 1 marks coverage).
    struct Value;

    impl FragmentShader for Value {
        type Varying = Vec2;
        fn fragment(&self, _: TriInfo, v: &Vec2) -> Option<Vec4> {
            Some(Vec4::new(v.x, v.y, 0.0, 1.0))
        }
    }

    /// Outputs the varying's derivatives (dx.x, dx.y, dy.x, dy.y).
    struct Derivatives;

    impl FragmentShader for Derivatives {
        type Varying = Vec2;
        const DERIVATIVES: bool = true;
        fn fragment(&self, _: TriInfo, _: &Vec2) -> Option<Vec4> {
            Some(Vec4::NAN) // must not be called
        }
        fn fragment_grad(&self, _: TriInfo, _: &Vec2, dx: &Vec2, dy: &Vec2) -> Option<Vec4> {
            Some(Vec4::new(dx.x, dx.y, dy.x, dy.y))
        }
    }

    const W: u32 = 96;
    const H: u32 = 72;

    fn render<S: FragmentShader<Varying = Vec2>>(
        clip: &[Vec4],
        var: &[Vec2],
        shader: &S,
    ) -> (Vec<Vec4>, Stats) {
        let mut target = Target::new(W, H, Vec4::ZERO);
        let mut stats = Stats::default();
        let d = Draw {
            id: 0,
            clip,
            varyings: var,
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
        let (value, stats) = render(clip, var, &Value);
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
}
