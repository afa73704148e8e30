//! The meshes' points and lines: their per-vertex colours, cut by the section planes, drawn
//! after the opaque surfaces.

use std::time::Instant;

use glam::Vec4;

use super::Cx;
use crate::frame::FrameData;
use crate::raster::{self, StrokeStyle};

/// The frame's points and lines and their vertex colours, kept in the pool between frames,
/// and what is left of them after the section planes.
#[derive(Default)]
pub(super) struct StrokeScratch {
    pub(super) clip: Vec<Vec4>,
    colors: Vec<Vec4>,
    pub(super) cut: Cut,
}

/// Points and lines cut by section planes: the kept ones, with the new ends of the lines
/// crossing a plane appended to the positions (and colours).
#[derive(Default)]
pub(super) struct Cut {
    pub(super) lines: Vec<[u32; 2]>,
    points: Vec<u32>,
}

impl Cut {
    /// Cuts `lines` and `points` of `clip` by `planes` (clip space, kept where
    /// `dot(plane, p) >= 0`), appending each new end to `clip` and, when given, its
    /// interpolated colour to `colors`.
    pub(super) fn cut(
        &mut self,
        planes: &[Vec4],
        clip: &mut Vec<Vec4>,
        mut colors: Option<&mut Vec<Vec4>>,
        lines: &[[u32; 2]],
        points: &[u32],
    ) {
        self.lines.clear();
        self.points.clear();
        let kept = |p: Vec4| planes.iter().all(|l| l.dot(p) >= 0.0);
        self.points.extend(
            points
                .iter()
                .filter(|&&i| clip.get(i as usize).is_some_and(|&p| kept(p))),
        );
        for &[i, j] in lines {
            let (Some(&a), Some(&b)) = (clip.get(i as usize), clip.get(j as usize)) else {
                continue;
            };
            // The part of a..b on the kept side of every plane: t in [t0, t1].
            let (mut t0, mut t1) = (0.0f32, 1.0f32);
            for l in planes {
                let (da, db) = (l.dot(a), l.dot(b));
                if da < 0.0 && db < 0.0 {
                    t1 = -1.0;
                    break;
                }
                if da < 0.0 {
                    t0 = t0.max(da / (da - db));
                } else if db < 0.0 {
                    t1 = t1.min(da / (da - db));
                }
            }
            if t0.is_nan() || t1.is_nan() || t0 > t1 {
                continue;
            }
            // The end at t: an existing vertex, or a new one.
            let mut end = |t: f32| -> u32 {
                if t == 0.0 {
                    return i;
                }
                if t == 1.0 {
                    return j;
                }
                clip.push(a + (b - a) * t);
                if let Some(c) = colors.as_deref_mut() {
                    let (ca, cb) = (c[i as usize], c[j as usize]);
                    c.push(ca + (cb - ca) * t);
                }
                (clip.len() - 1) as u32
            };
            let e0 = end(t0);
            let e1 = end(t1);
            self.lines.push([e0, e1]);
        }
    }
}

/// The points and lines of every visible instance that has some, after the opaque
/// surfaces and wireframe and before the blended surfaces: per-vertex colours
/// ([`Lit::strokes`]), then [`raster::draw_points`] and [`raster::draw_wide_lines`]
/// (serial, in instance order: the same image for any thread count). Returns false if
/// stopped.
pub(super) fn strokes(cx: &mut Cx, fd: &FrameData) -> bool {
    if !fd.insts.iter().any(|fi| fi.strokes) {
        return true;
    }
    let lit = super::lit_of(cx, fd);
    let mut s = cx.pool.take::<StrokeScratch>();
    let mut done = true;
    for fi in fd.insts.iter().filter(|fi| fi.strokes) {
        if (cx.stop)() {
            done = false;
            break;
        }
        let tri = &cx.scene.meshes[fi.mesh as usize].tri;
        let start = Instant::now();
        s.clip.clear();
        raster::transform_positions_into(cx.jitter * fi.mvp, &tri.positions, &mut s.clip);
        lit.strokes(fi, &mut s.colors);
        cx.vertex_nanos += start.elapsed().as_nanos() as u64;
        let point = StrokeStyle {
            size: fd.point_size,
            blend: fi.blend,
        };
        let line = StrokeStyle {
            size: fd.line_width,
            blend: fi.blend,
        };
        let StrokeScratch { clip, colors, cut } = &mut *s;
        let (points, lines) = if cx.sections.is_empty() {
            (&tri.points[..], &tri.lines[..])
        } else {
            cut.cut(cx.sections, clip, Some(colors), &tri.lines, &tri.points);
            (&cut.points[..], &cut.lines[..])
        };
        raster::draw_points(cx.target, clip, colors, points, &point, cx.stats);
        raster::draw_wide_lines(cx.target, clip, colors, lines, &line, cx.stats);
    }
    cx.pool.put(s);
    done
}
