//! Lines and points: the textbook's Bresenham line primitive with a depth test, for
//! wireframe ([`draw_lines`]), and the points and lines of meshes ([`draw_points`],
//! [`draw_wide_lines`]: a size and width in pixels, per-vertex colours).
//!
//! A wireframe line is clipped in homogeneous space against the near and far planes, projected, clipped
//! to the viewport (Liang-Barsky), then stepped with integer Bresenham from the pixel holding
//! one end point to the pixel holding the other. Depth (z/w, affine in screen space) is
//! interpolated along the line. Lines are drawn serially in submission order (deterministic
//! for any thread count); they are cheap next to triangle fill. The pixel rules of points
//! and wide lines are stated on [`draw_points`] and [`draw_wide_lines`]; both share the
//! Bresenham stepping ([`steps`]) with wireframe, so a 1-pixel mesh line covers the pixels a
//! wireframe edge between the same points does.

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

/// The part of a screen segment in [0, w) x [0, h) (Liang-Barsky); z is interpolated along.
fn clip_to_rect(a: Vec4, b: Vec4, w: f32, h: f32) -> Option<(Vec4, Vec4)> {
    let hi = [w - 1e-3, h - 1e-3];
    let (t0, t1) = crate::geom::clip_segment([a.x, a.y], [b.x, b.y], [0.0, 0.0], hi)?;
    let d = b - a;
    Some((a + d * t0, a + d * t1))
}

fn bresenham(target: &mut Target, depth: Option<&DepthCopy>, a: Vec4, b: Vec4, style: &LineStyle) {
    let clamp_x = |v: f32| (v.floor() as i64).clamp(0, i64::from(target.width) - 1);
    let clamp_y = |v: f32| (v.floor() as i64).clamp(0, i64::from(target.height) - 1);
    let from = (clamp_x(a.x), clamp_y(a.y));
    let to = (clamp_x(b.x), clamp_y(b.y));
    steps(from, to, |x, y, s| {
        let z = a.z + (b.z - a.z) * s;
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
    });
}

/// Integer Bresenham from pixel `from` to pixel `to`, both included: `plot(x, y, s)` for
/// every pixel, one per step along the major axis, `s` = step / steps in [0, 1] (0 for a
/// single pixel). The pixels form an 8-connected path.
fn steps(from: (i64, i64), to: (i64, i64), mut plot: impl FnMut(i64, i64, f32)) {
    let (mut x, mut y) = from;
    let (x1, y1) = to;
    let dx = (x1 - x).abs();
    let dy = -(y1 - y).abs();
    let (sx, sy) = (if x < x1 { 1 } else { -1 }, if y < y1 { 1 } else { -1 });
    let steps = dx.max(-dy).max(1) as f32;
    let mut err = dx + dy;
    let mut i = 0.0f32;
    loop {
        plot(x, y, i / steps);
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

/// Largest point size and line width, in pixels: larger values are drawn at this size.
pub const MAX_STROKE_PX: f32 = 64.0;

/// How a mesh's points and lines are drawn ([`draw_points`], [`draw_wide_lines`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrokeStyle {
    /// Point size, or line width, in pixels: rounded to a whole number of pixels, at least 1
    /// and at most [`MAX_STROKE_PX`] (a non-finite value draws 1 pixel).
    pub size: f32,
    /// Blend over what is there by the colour's alpha (a blended material); else replace.
    pub blend: bool,
}

impl StrokeStyle {
    /// The size in whole pixels (1 ..= [`MAX_STROKE_PX`]).
    #[must_use]
    pub fn pixels(&self) -> i64 {
        if self.size.is_finite() {
            self.size.round().clamp(1.0, MAX_STROKE_PX) as i64
        } else {
            1
        }
    }
}

/// The first offset of a run of `n` pixels centred on a pixel: `-floor((n - 1) / 2)`, so an
/// odd run is centred and an even one has its extra pixel on the positive side (right, or
/// below).
fn run_start(n: i64) -> i64 {
    -((n - 1) / 2)
}

/// Writes colour `c` at depth `z` to pixel (x, y) if it is inside the target and passes the
/// depth test (`z >= depth`, reversed-Z: nearer or equal wins); raises the depth.
#[inline]
fn stroke_pixel(target: &mut Target, x: i64, y: i64, z: f32, c: Vec4, blend: bool) -> bool {
    if x < 0 || y < 0 || x >= i64::from(target.width) || y >= i64::from(target.height) {
        return false;
    }
    let (t, o) = target.locate(x as u32, y as u32);
    let tile = &mut target.tiles[t];
    if z < tile.depth_at(o) {
        return false;
    }
    tile.materialize();
    let out = if blend {
        tile.color_at(o).lerp(c, c.w.clamp(0.0, 1.0))
    } else {
        c
    };
    tile.set_color(o, out);
    tile.raise_depth(o, z);
    true
}

/// Screen position (pixels, y down) and depth (z/w) of a clip-space point with `w > 0`.
#[inline]
fn to_screen(p: Vec4, w: f32, h: f32) -> Vec4 {
    let iw = 1.0 / p.w;
    Vec4::new(
        (p.x * iw + 1.0) * 0.5 * w,
        (1.0 - p.y * iw) * 0.5 * h,
        p.z * iw,
        0.0,
    )
}

/// Draws `points` (indices into `clip` and `colors`, which are parallel) as squares of
/// `style.pixels()` = n pixels: the point's pixel is the one holding its projected
/// position (whose centre is nearest it), and the square spans `floor((n - 1) / 2)` pixels
/// before it and `floor(n / 2)` after it on each axis. A point outside the near or far
/// plane, or behind the eye, is not drawn; a square is cut by the viewport's edges. Every
/// pixel of the square has the point's depth and passes where it is at least as near as
/// the depth buffer. Points are drawn serially in order: the same image for any thread
/// count.
pub fn draw_points(
    target: &mut Target,
    clip: &[Vec4],
    colors: &[Vec4],
    points: &[u32],
    style: &StrokeStyle,
    stats: &mut Stats,
) {
    let (w, h) = (target.width as f32, target.height as f32);
    let n = style.pixels();
    let lo = run_start(n);
    for &k in points {
        let (Some(&p), Some(&c)) = (clip.get(k as usize), colors.get(k as usize)) else {
            continue;
        };
        if !p.is_finite() || p.w <= 0.0 || outcode(p, Vec2::splat(f32::MAX)) != 0 {
            continue;
        }
        let s = to_screen(p, w, h);
        // Far outside the viewport (also keeps the casts below in range).
        let reach = n as f32 + 1.0;
        if !(s.x > -reach && s.x < w + reach && s.y > -reach && s.y < h + reach) {
            continue;
        }
        let (cx, cy) = (s.x.floor() as i64, s.y.floor() as i64);
        let mut any = false;
        for y in cy + lo..cy + lo + n {
            for x in cx + lo..cx + lo + n {
                any |= stroke_pixel(target, x, y, s.z, c, style.blend);
            }
        }
        stats.points_drawn += u64::from(any);
    }
}

/// Clips segment `a`-`b` (clip space) to the near and far planes and to the frustum's sides
/// widened by the factors `g`, returning the parameters `(t0, t1)` of the part kept.
fn clip_segment(a: Vec4, b: Vec4, g: Vec2) -> Option<(f32, f32)> {
    crate::geom::clip_interval([
        (a.w - a.z, b.w - b.z),
        (a.z, b.z),
        (a.x + g.x * a.w, b.x + g.x * b.w),
        (g.x * a.w - a.x, g.x * b.w - b.x),
        (a.y + g.y * a.w, b.y + g.y * b.w),
        (g.y * a.w - a.y, g.y * b.w - b.y),
    ])
}

/// Draws `lines` (pairs of indices into `clip` and `colors`, which are parallel) with the
/// textbook's Bresenham stepping, `style.pixels()` = n pixels wide: from the pixel holding
/// one end to the pixel holding the other, both included, one pixel per step along the
/// major axis (an 8-connected path); a wider line repeats each pixel across the minor axis
/// (a column of n pixels for an x-major line, a row for a y-major one), spanning
/// `floor((n - 1) / 2)` pixels before it and `floor(n / 2)` after. Colour and depth (z/w)
/// are interpolated linearly along the steps; every pixel passes where it is at least as
/// near as the depth buffer. Segments are clipped in clip space against the near and far
/// planes and against the frustum's sides widened by the line's width plus two pixels (so
/// coordinates stay small and a wide line along an edge keeps its visible part); pixels
/// outside the viewport are skipped. Lines are drawn serially in order: the same image for
/// any thread count.
pub fn draw_wide_lines(
    target: &mut Target,
    clip: &[Vec4],
    colors: &[Vec4],
    lines: &[[u32; 2]],
    style: &StrokeStyle,
    stats: &mut Stats,
) {
    let (w, h) = (target.width as f32, target.height as f32);
    let n = style.pixels();
    let lo = run_start(n);
    let margin = n as f32 + 2.0;
    let g = Vec2::new(1.0 + 2.0 * margin / w, 1.0 + 2.0 * margin / h);
    for l in lines {
        let at = |k: u32| Some((*clip.get(k as usize)?, *colors.get(k as usize)?));
        let (Some((a, ca)), Some((b, cb))) = (at(l[0]), at(l[1])) else {
            continue;
        };
        if !a.is_finite() || !b.is_finite() {
            continue;
        }
        let Some((t0, t1)) = clip_segment(a, b, g) else {
            continue;
        };
        let (pa, pb) = (a.lerp(b, t0), a.lerp(b, t1));
        let (ca, cb) = (ca.lerp(cb, t0), ca.lerp(cb, t1));
        if pa.w <= 0.0 || pb.w <= 0.0 {
            continue;
        }
        let (sa, sb) = (to_screen(pa, w, h), to_screen(pb, w, h));
        if !sa.is_finite() || !sb.is_finite() {
            continue;
        }
        let pixel = |s: Vec4| (s.x.floor() as i64, s.y.floor() as i64);
        let (from, to) = (pixel(sa), pixel(sb));
        let x_major = (to.0 - from.0).abs() >= (to.1 - from.1).abs();
        let mut any = false;
        steps(from, to, |x, y, s| {
            let z = sa.z + (sb.z - sa.z) * s;
            let c = ca.lerp(cb, s);
            for k in lo..lo + n {
                let (px, py) = if x_major { (x, y + k) } else { (x + k, y) };
                any |= stroke_pixel(target, px, py, z, c, style.blend);
            }
        });
        stats.lines_drawn += u64::from(any);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const BG: Vec4 = Vec4::new(0.0, 0.0, 0.0, 1.0);
    const RED: Vec4 = Vec4::new(1.0, 0.0, 0.0, 1.0);

    /// The clip position (w = 1) of screen point (x, y) at depth z on a w x h target.
    fn at(x: f32, y: f32, z: f32, w: u32, h: u32) -> Vec4 {
        Vec4::new(2.0 * x / w as f32 - 1.0, 1.0 - 2.0 * y / h as f32, z, 1.0)
    }

    /// The pixels whose colour is not the background, row by row.
    fn covered(t: &Target) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        for y in 0..t.height {
            for x in 0..t.width {
                if t.pixel(x, y).expect("inside").0 != BG {
                    out.push((x, y));
                }
            }
        }
        out
    }

    fn style(size: f32) -> StrokeStyle {
        StrokeStyle { size, blend: false }
    }

    #[test]
    fn a_point_covers_the_pixel_nearest_it_and_a_square_around_it() {
        let (w, h) = (16, 12);
        for (size, want_x, want_y) in [
            (1.0, 5..=5, 7..=7),
            (2.0, 5..=6, 7..=8),
            (3.0, 4..=6, 6..=8),
            // Rounded to whole pixels.
            (3.4, 4..=6, 6..=8),
        ] {
            let mut t = Target::new(w, h, BG);
            let clip = [at(5.3, 7.8, 0.5, w, h)];
            let mut stats = Stats::default();
            draw_points(&mut t, &clip, &[RED], &[0], &style(size), &mut stats);
            let want: Vec<(u32, u32)> = want_y
                .flat_map(|y| want_x.clone().map(move |x| (x, y)))
                .collect();
            assert_eq!(covered(&t), want, "size {size}");
            assert_eq!(stats.points_drawn, 1);
        }
        // A square cut by the edge keeps its inside part; one outside draws nothing.
        let mut t = Target::new(w, h, BG);
        let clip = [at(0.2, 0.7, 0.5, w, h), at(-9.0, 3.0, 0.5, w, h)];
        let mut stats = Stats::default();
        draw_points(&mut t, &clip, &[RED; 2], &[0, 1], &style(3.0), &mut stats);
        assert_eq!(covered(&t), vec![(0, 0), (1, 0), (0, 1), (1, 1)]);
        assert_eq!(stats.points_drawn, 1);
        // Behind the near plane or past the far plane: not drawn.
        let mut t = Target::new(w, h, BG);
        let clip = [at(5.5, 5.5, 1.5, w, h), at(6.5, 5.5, -0.5, w, h)];
        draw_points(&mut t, &clip, &[RED; 2], &[0, 1], &style(1.0), &mut stats);
        assert!(covered(&t).is_empty());
    }

    #[test]
    fn a_line_covers_one_pixel_per_major_axis_step() {
        let (w, h) = (32, 16);
        let clip = [at(2.5, 3.5, 0.5, w, h), at(20.5, 9.5, 0.5, w, h)];
        for width in [1.0f32, 3.0] {
            let mut t = Target::new(w, h, BG);
            let mut stats = Stats::default();
            draw_wide_lines(
                &mut t,
                &clip,
                &[RED; 2],
                &[[0, 1]],
                &style(width),
                &mut stats,
            );
            let px = covered(&t);
            // One pixel (or `width` pixels in a column) for each x from 2 to 20.
            assert_eq!(px.len(), 19 * width as usize, "width {width}");
            for x in 2..=20 {
                let column: Vec<u32> = px.iter().filter(|p| p.0 == x).map(|p| p.1).collect();
                assert_eq!(column.len(), width as usize, "column {x}");
                assert!(column.windows(2).all(|c| c[1] == c[0] + 1), "{column:?}");
            }
            // The ends are the pixels holding them (the middle of a 3-pixel column).
            let mid =
                |x: u32, y: u32| px.contains(&(x, y)) && px.contains(&(x, y + width as u32 / 2));
            assert!(mid(2, 3) && mid(20, 9));
            assert_eq!(stats.lines_drawn, 1);
        }
        // A steep (y-major) line: one pixel per row.
        let mut t = Target::new(w, h, BG);
        let clip = [at(4.5, 1.5, 0.5, w, h), at(7.5, 14.5, 0.5, w, h)];
        let mut stats = Stats::default();
        draw_wide_lines(&mut t, &clip, &[RED; 2], &[[0, 1]], &style(1.0), &mut stats);
        let px = covered(&t);
        assert_eq!(px.len(), 14);
        for y in 1..=14 {
            assert_eq!(px.iter().filter(|p| p.1 == y).count(), 1, "row {y}");
        }
    }

    #[test]
    fn lines_and_points_hide_behind_nearer_depth() {
        let (w, h) = (32, 8);
        let mut t = Target::new(w, h, BG);
        // A nearer surface (reversed-Z: larger is nearer) over x = 10..20.
        for y in 0..h {
            for x in 10..20 {
                let (tile, o) = t.locate(x, y);
                t.tiles[tile].materialize();
                t.tiles[tile].raise_depth(o, 0.8);
            }
        }
        let clip = [
            at(0.5, 4.5, 0.5, w, h),
            at(31.5, 4.5, 0.5, w, h),
            at(15.5, 2.5, 0.5, w, h),
        ];
        let mut stats = Stats::default();
        draw_wide_lines(&mut t, &clip, &[RED; 3], &[[0, 1]], &style(1.0), &mut stats);
        draw_points(&mut t, &clip, &[RED; 3], &[2], &style(1.0), &mut stats);
        let px = covered(&t);
        assert_eq!(px.len(), 22);
        assert!(px.iter().all(|&(x, y)| y == 4 && !(10..20).contains(&x)));
        assert_eq!(stats.points_drawn, 0);
    }

    #[test]
    fn lines_are_clipped_to_near_far_and_the_viewport() {
        let (w, h) = (16, 16);
        let mut t = Target::new(w, h, BG);
        // One end behind the eye (w < 0), one end far outside: no panic, finite work, and
        // only pixels inside.
        let clip = [
            Vec4::new(0.0, 0.0, 0.5, 1.0),
            Vec4::new(0.3, 0.1, 2.0, -1.0),
            Vec4::new(1e30, 0.0, 0.5, 1.0),
            Vec4::new(f32::NAN, 0.0, 0.5, 1.0),
        ];
        let lines = [[0, 1], [0, 2], [0, 3], [2, 9]];
        let mut stats = Stats::default();
        draw_wide_lines(&mut t, &clip, &[RED; 4], &lines, &style(64.0), &mut stats);
        assert!(stats.lines_drawn >= 1);
        // The segment towards +x from the centre reaches the right edge.
        let px = covered(&t);
        assert!(px.contains(&(15, 8)), "{px:?}");
    }
}
