//! Lines: the textbook's Bresenham line primitive with a depth test, for wireframe.
//!
//! A line is clipped in homogeneous space against the near and far planes, projected, clipped
//! to the viewport (Liang-Barsky), then stepped with integer Bresenham from the pixel holding
//! one end point to the pixel holding the other. Depth (z/w, affine in screen space) is
//! interpolated along the line. Lines are drawn serially in submission order (deterministic
//! for any thread count); they are cheap next to triangle fill.

use glam::{Vec2, Vec4};

use super::clip::{clip_polygon, outcode, ClipVertex, Poly, FAR, NEAR};
use super::framebuffer::{DepthCopy, Target};
use super::pipeline::Stats;

/// How lines are drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineStyle {
    /// Linear RGBA written to covered pixels (replaces the colour).
    pub color: Vec4,
    /// Test against depth; a line pixel passes if `z >= depth * (1 - depth_tolerance)`.
    pub depth_test: bool,
    /// Relative depth tolerance so edges of a surface win against the surface itself
    /// (reversed-Z depth is about near/distance, so 1e-3 is 0.1% of the distance).
    pub depth_tolerance: f32,
    pub depth_write: bool,
}

/// Draws `lines` (pairs of indices into `clip`) into `target`. When `depth` is given (as from
/// [`Target::restore_depth`]) lines test against it instead of the target's own depth.
pub fn draw_lines(
    target: &mut Target,
    depth: Option<&DepthCopy>,
    clip: &[Vec4],
    lines: &[[u32; 2]],
    style: &LineStyle,
    stats: &mut Stats,
) {
    let (w, h) = (target.width as f32, target.height as f32);
    for l in lines {
        let (Some(&a), Some(&b)) = (clip.get(l[0] as usize), clip.get(l[1] as usize)) else {
            continue;
        };
        if !a.is_finite() || !b.is_finite() {
            continue;
        }
        let (oa, ob) = (outcode(a, Vec2::ONE), outcode(b, Vec2::ONE));
        if oa & ob != 0 {
            continue;
        }
        let (a, b) = if (oa | ob) & (NEAR | FAR) != 0 {
            // A degenerate "polygon" a-b-a clips exactly like the segment.
            let v = |p: Vec4| ClipVertex::new(p, &[]);
            let tri = Poly::triangle([v(a), v(b), v(a)], 0);
            let poly = clip_polygon(tri, (oa | ob) & (NEAR | FAR), Vec2::ONE);
            let poly = poly.as_slice();
            if poly.len() < 2 {
                continue;
            }
            let (mut lo, mut hi) = (poly[0].pos, poly[0].pos);
            // The clipped segment's ends are the two points farthest apart.
            let mut best = -1.0;
            for p in poly {
                for q in poly {
                    let d = (p.pos - q.pos).length_squared();
                    if d > best {
                        best = d;
                        (lo, hi) = (p.pos, q.pos);
                    }
                }
            }
            (lo, hi)
        } else {
            (a, b)
        };
        if a.w <= 0.0 || b.w <= 0.0 {
            continue;
        }
        let screen = |p: Vec4| {
            let iw = 1.0 / p.w;
            Vec4::new(
                (p.x * iw + 1.0) * 0.5 * w,
                (1.0 - p.y * iw) * 0.5 * h,
                p.z * iw,
                0.0,
            )
        };
        let (sa, sb) = (screen(a), screen(b));
        let Some((sa, sb)) = clip_to_rect(sa, sb, w, h) else {
            continue;
        };
        stats.lines_drawn += 1;
        bresenham(target, depth, sa, sb, style);
    }
}

/// Liang-Barsky clip of a screen segment to [0, w) x [0, h); z is interpolated along.
fn clip_to_rect(a: Vec4, b: Vec4, w: f32, h: f32) -> Option<(Vec4, Vec4)> {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    let lim_x = w - 1e-3;
    let lim_y = h - 1e-3;
    for (p, q) in [
        (-d.x, a.x),
        (d.x, lim_x - a.x),
        (-d.y, a.y),
        (d.y, lim_y - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then(|| (a + d * t0, a + d * t1))
}

fn bresenham(target: &mut Target, depth: Option<&DepthCopy>, a: Vec4, b: Vec4, style: &LineStyle) {
    let clamp_x = |v: f32| (v.floor() as i64).clamp(0, i64::from(target.width) - 1);
    let clamp_y = |v: f32| (v.floor() as i64).clamp(0, i64::from(target.height) - 1);
    let (mut x, mut y) = (clamp_x(a.x), clamp_y(a.y));
    let (x1, y1) = (clamp_x(b.x), clamp_y(b.y));
    let dx = (x1 - x).abs();
    let dy = -(y1 - y).abs();
    let (sx, sy) = (if x < x1 { 1 } else { -1 }, if y < y1 { 1 } else { -1 });
    let steps = dx.max(-dy).max(1) as f32;
    let mut err = dx + dy;
    let mut i = 0.0f32;
    loop {
        let z = a.z + (b.z - a.z) * (i / steps);
        let (t, o) = target.locate(x as u32, y as u32);
        let d = depth.map_or(target.tiles[t].depth_at(o), |d| d.at(t, o));
        if !style.depth_test || z >= d * (1.0 - style.depth_tolerance) {
            let tile = &mut target.tiles[t];
            tile.materialize();
            tile.set_color(o, style.color);
            if style.depth_write {
                tile.raise_depth(o, z);
            }
        }
        if x == x1 && y == y1 {
            break;
        }
        let e2 = 2 * err;
        if e2 >= dy {
            err += dy;
            x += sx;
        }
        if e2 <= dx {
            err += dx;
            y += sy;
        }
        i += 1.0;
    }
}
