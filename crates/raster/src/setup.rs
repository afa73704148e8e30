//! Fixed-point triangle setup.
//!
//! Screen coordinates are snapped to 1/256 pixel ([`SUBPIXEL_BITS`] = 8) with round-half-to-even
//! and the three edge functions are evaluated exactly in i64:
//!
//! `E_k(P) = a_k * P.x + b_k * P.y + c_k`, for the edge from vertex k+1 to vertex k+2,
//!
//! which is twice the signed area of the triangle (edge, P): positive on the inside once the
//! triangle is oriented with positive area. `E_0 + E_1 + E_2` = twice the triangle's area for
//! every P, so `E_k / area` are the screen-space barycentric coordinates.
//!
//! Fill rule (top-left, as Direct3D and OpenGL): a sample exactly on an edge belongs to the
//! triangle only if the edge is a *left* edge (the inside lies towards +x: `a > 0`) or a *top*
//! edge (horizontal with the inside below, y pointing down: `a == 0 && b > 0`). This is a bias
//! of -1 on the other edges' integer functions, so shared edges are covered exactly once.
//!
//! Magnitudes: after guard-band clipping, |coordinate| < 2^23 fixed units, so `a`, `b` < 2^24
//! and `E` < 2^49: i64 never overflows.

use glam::Vec4;

use super::clip::ClipVertex;
use super::pipeline::{Cull, DrawState};
use super::TriInfo;

/// Sub-pixel precision of snapped vertices: 1/256 pixel.
pub const SUBPIXEL_BITS: u32 = 8;
pub(crate) const ONE: i64 = 1 << SUBPIXEL_BITS;
const HALF: i64 = ONE / 2;
/// How far (pixels) outside the viewport a vertex may lie before the triangle is clipped.
pub const GUARD_BAND_PX: f32 = 8192.0;
/// Largest absolute fixed-point coordinate accepted (clamp after clipping's rounding).
const MAX_COORD: f32 = (1u32 << 23) as f32;

/// A triangle ready to fill. Vertices are ordered so the area is positive. Its varyings are
/// stored next to it, in its chunk's attribute buffer (see [`setup`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct SetupTri {
    /// Edge function coefficients (unbiased): `a`, `b` < 2^24 in magnitude (see the
    /// module docs), `c` < 2^49.
    pub a: [i32; 3],
    pub b: [i32; 3],
    pub c: [i64; 3],
    /// Bit k set if edge k is a top or left edge: inside iff `E_k + bias(k) >= 0` for all k.
    pub top_left: u8,
    /// Inclusive pixel bounds, clamped to the target.
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
    /// 1 / (twice the area), in fixed units.
    pub inv_area: f32,
    /// Depth (z/w) at vertex 0, and its differences to vertices 1 and 2.
    pub z: [f32; 3],
    /// 1/w at the three vertices.
    pub iw: [f32; 3],
    /// Offset of the varyings in the attribute buffer: `stride` floats of vertex 0, then
    /// the differences to vertex 1, then to vertex 2, each row padded to [`padded`] floats.
    pub attr: u32,
    pub stride: u8,
    pub info: TriInfo,
    pub state: DrawState,
}

/// `stride` rounded up to a multiple of 4: the length of each row of a triangle's stored
/// varyings.
#[inline(always)]
pub(crate) fn padded(stride: usize) -> usize {
    stride.div_ceil(4) * 4
}

impl SetupTri {
    /// 0 for a top-left edge, -1 otherwise.
    #[inline(always)]
    pub fn bias(&self, k: usize) -> i64 {
        i64::from(self.top_left >> k & 1) - 1
    }

    /// `a[k]`, `b[k]` widened for the i64 edge arithmetic.
    #[inline(always)]
    pub fn ab(&self, k: usize) -> (i64, i64) {
        (i64::from(self.a[k]), i64::from(self.b[k]))
    }
}

/// Why a triangle produced nothing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Reject {
    Backface,
    /// Zero area after snapping, or no pixel centre inside its bounds.
    Degenerate,
}

/// Where a triangle's vertices come from: clip positions and `stride` varyings each.
#[derive(Clone, Copy)]
pub(crate) struct Corners<'a> {
    pub pos: [Vec4; 3],
    pub var: [&'a [f32]; 3],
}

impl<'a> Corners<'a> {
    pub fn of(v: [&'a ClipVertex; 3], stride: usize) -> Self {
        Self {
            pos: [v[0].pos, v[1].pos, v[2].pos],
            var: [
                &v[0].var[..stride],
                &v[1].var[..stride],
                &v[2].var[..stride],
            ],
        }
    }
}

/// A vertex after the perspective divide and snapping: fixed-point screen position, depth
/// z/w and 1/w.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct ScreenVert {
    pub x: i64,
    pub y: i64,
    pub z: f32,
    pub iw: f32,
}

/// Projects and snaps clip-space `p` for a target of half-size `hw` x `hh`; `None` where
/// w is not positive (clipping leaves w >= near > 0; w <= 0 only reaches here from a
/// vertex no plane test caught, such as (0, 0, 0, 0)).
#[inline(always)]
pub(crate) fn project(p: Vec4, hw: f32, hh: f32, bits: u8) -> Option<ScreenVert> {
    if p.w.is_nan() || p.w <= 0.0 {
        return None;
    }
    let inv_w = 1.0 / p.w;
    let sx = (p.x * inv_w + 1.0) * hw;
    let sy = (1.0 - p.y * inv_w) * hh;
    Some(ScreenVert {
        x: snap(sx, bits),
        y: snap(sy, bits),
        z: p.z * inv_w,
        iw: inv_w,
    })
}

/// [`project`] of a triangle's three vertices; `None` if any has w <= 0.
#[inline(always)]
pub(crate) fn project3(pos: [Vec4; 3], hw: f32, hh: f32, bits: u8) -> Option<[ScreenVert; 3]> {
    Some([
        project(pos[0], hw, hh, bits)?,
        project(pos[1], hw, hh, bits)?,
        project(pos[2], hw, hh, bits)?,
    ])
}

/// Sets up one (clipped) triangle for a `width` x `height` target; on success its varyings
/// are appended to `attrs`. (The pipeline projects vertices first and calls
/// [`setup_projected`]; this is the whole step, for tests.)
#[cfg(test)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn setup<'a>(
    v: Corners<'a>,
    width: u32,
    height: u32,
    draw: u32,
    state: DrawState,
    ccw: Option<bool>,
    attrs: &mut Vec<f32>,
) -> Result<SetupTri, Reject> {
    let (hw, hh) = (width as f32 * 0.5, height as f32 * 0.5);
    let s = project3(v.pos, hw, hh, state.subpixel_bits).ok_or(Reject::Degenerate)?;
    let vp = Viewport {
        width,
        height,
        reach: 0,
    };
    setup_projected(s, v.var, vp, draw, state, ccw, attrs)
}

/// The target as set-up sees it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Viewport {
    /// Size in pixels.
    pub width: u32,
    pub height: u32,
    /// How far the target's samples lie from the pixel centre, along x or y at most, in
    /// fixed-point units (0 with one sample per pixel): a pixel is a candidate when its
    /// centre is within `reach` of the triangle's bounding box.
    pub reach: i64,
}

/// [`setup`] of a triangle whose vertices are already projected and snapped (the
/// pipeline projects each vertex once, not once per triangle using it).
#[inline(always)]
pub(crate) fn setup_projected<'a>(
    s: [ScreenVert; 3],
    var: [&'a [f32]; 3],
    vp: Viewport,
    draw: u32,
    state: DrawState,
    ccw: Option<bool>,
    attrs: &mut Vec<f32>,
) -> Result<SetupTri, Reject> {
    let x = [s[0].x, s[1].x, s[2].x];
    let y = [s[0].y, s[1].y, s[2].y];
    let z = [s[0].z, s[1].z, s[2].z];
    let iw = [s[0].iw, s[1].iw, s[2].iw];
    let mut order = [0usize, 1, 2];
    let area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
    if area == 0 {
        return Err(Reject::Degenerate);
    }
    // Counter-clockwise in NDC (y up) is clockwise on screen (y down): negative area here.
    // A piece of a clipped triangle must keep the triangle's orientation: an inverted piece
    // is an f32 rounding artefact of a vertex near w = 0 (a sliver folded over its
    // neighbour), and drawing it would cover pixels twice.
    if ccw.is_some_and(|ccw| (area < 0) != ccw) {
        return Err(Reject::Degenerate);
    }
    let front = (area < 0) != state.flip_winding;
    match state.cull {
        Cull::Back if !front => return Err(Reject::Backface),
        Cull::Front if front => return Err(Reject::Backface),
        _ => {}
    }
    if area < 0 {
        order = [0, 2, 1];
    }
    let [i0, i1, i2] = order;
    let (xs, ys) = ([x[i0], x[i1], x[i2]], [y[i0], y[i1], y[i2]]);

    let min_x = xs[0].min(xs[1]).min(xs[2]);
    let max_x = xs[0].max(xs[1]).max(xs[2]);
    let min_y = ys[0].min(ys[1]).min(ys[2]);
    let max_y = ys[0].max(ys[1]).max(ys[2]);
    // Pixel p is a candidate if its centre p * ONE + HALF lies within [min - reach,
    // max + reach] (one of its samples may lie inside).
    let r = vp.reach;
    let px0 = ceil_div(min_x - HALF - r, ONE).max(0);
    let py0 = ceil_div(min_y - HALF - r, ONE).max(0);
    let px1 = (max_x - HALF + r)
        .div_euclid(ONE)
        .min(i64::from(vp.width) - 1);
    let py1 = (max_y - HALF + r)
        .div_euclid(ONE)
        .min(i64::from(vp.height) - 1);
    if px0 > px1 || py0 > py1 {
        return Err(Reject::Degenerate);
    }

    let mut a = [0i64; 3];
    let mut b = [0i64; 3];
    let mut c = [0i64; 3];
    let mut top_left_bits = 0u8;
    for k in 0..3 {
        // Edge k runs from vertex k+1 to vertex k+2 (opposite vertex k).
        let (s, e) = ((k + 1) % 3, (k + 2) % 3);
        a[k] = ys[s] - ys[e];
        b[k] = xs[e] - xs[s];
        c[k] = -(a[k] * xs[s] + b[k] * ys[s]);
        let top_left = a[k] > 0 || (a[k] == 0 && b[k] > 0);
        top_left_bits |= u8::from(top_left) << k;
    }
    let inv_area = 1.0 / area.abs() as f32;
    let dz = [z[i1] - z[i0], z[i2] - z[i0]];
    let mut z0 = z[i0];
    if state.depth_offset != 0.0 {
        // dλ_k/dx = a_k * ONE / area (per pixel), so dz/dx = Σ dz_k a_k ONE / area.
        let scale = ONE as f32 * inv_area;
        let dzdx = (a[1] as f32 * dz[0] + a[2] as f32 * dz[1]) * scale;
        let dzdy = (b[1] as f32 * dz[0] + b[2] as f32 * dz[1]) * scale;
        // Reversed-Z: away from the eye is smaller.
        z0 -= state.depth_offset * dzdx.abs().max(dzdy.abs());
    }
    let (mut stride, mut first) = (var[0].len(), 0);
    if state.facing_varyings {
        stride /= 2;
        first = if front { 0 } else { stride };
    }
    let attr = attrs.len() as u32;
    let half = |s: &'a [f32]| &s[first..first + stride];
    let (v0, v1, v2) = (half(var[i0]), half(var[i1]), half(var[i2]));
    // Each of the three rows padded with zeros to a multiple of 4 floats, so the fill
    // interpolates in fixed groups of four (see `padded`).
    let pad = padded(stride) - stride;
    attrs.extend_from_slice(v0);
    attrs.extend(std::iter::repeat_n(0.0, pad));
    attrs.extend(v1.iter().zip(v0).map(|(a, b)| a - b));
    attrs.extend(std::iter::repeat_n(0.0, pad));
    attrs.extend(v2.iter().zip(v0).map(|(a, b)| a - b));
    attrs.extend(std::iter::repeat_n(0.0, pad));
    Ok(SetupTri {
        // Written out: `array::map` here was compiled out of line (a call per triangle).
        a: [a[0] as i32, a[1] as i32, a[2] as i32],
        b: [b[0] as i32, b[1] as i32, b[2] as i32],
        c,
        top_left: top_left_bits,
        x0: px0 as u32,
        y0: py0 as u32,
        x1: px1 as u32,
        y1: py1 as u32,
        inv_area,
        z: [z0, dz[0], dz[1]],
        iw: [iw[i0], iw[i1], iw[i2]],
        attr,
        stride: stride as u8,
        info: TriInfo { draw, front },
        state,
    })
}

/// Screen coordinate -> fixed point, rounded half to even on a grid of 2^-`bits` pixel
/// (`bits` capped at [`SUBPIXEL_BITS`]), in units of 1/[`ONE`].
#[inline(always)]
fn snap(s: f32, bits: u8) -> i64 {
    let coarse = SUBPIXEL_BITS.saturating_sub(u32::from(bits));
    if coarse == 0 {
        return (s * ONE as f32)
            .clamp(-MAX_COORD, MAX_COORD)
            .round_ties_even() as i64;
    }
    // Scaling by a power of two is exact, so this rounds `s` itself to the coarser grid.
    let scale = (1i64 << (SUBPIXEL_BITS - coarse)) as f32;
    let limit = MAX_COORD / (1i64 << coarse) as f32;
    ((s * scale).clamp(-limit, limit).round_ties_even() as i64) << coarse
}

#[inline]
fn ceil_div(n: i64, d: i64) -> i64 {
    -((-n).div_euclid(d))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cv(x: f32, y: f32) -> ClipVertex {
        ClipVertex::new(Vec4::new(x, y, 0.5, 1.0), &[])
    }

    fn run(v: [&ClipVertex; 3], w: u32, h: u32, cull: Cull) -> Result<SetupTri, Reject> {
        setup(
            Corners::of(v, 0),
            w,
            h,
            0,
            state(cull),
            None,
            &mut Vec::new(),
        )
    }

    fn state(cull: Cull) -> DrawState {
        DrawState {
            cull,
            ..DrawState::opaque()
        }
    }

    #[test]
    fn snap_rounds_half_to_even() {
        for (s, want) in [
            (0.5 / 256.0, 0),
            (1.5 / 256.0, 2),
            (2.5 / 256.0, 2),
            (-0.5 / 256.0, 0),
            (-1.5 / 256.0, -2),
        ] {
            assert_eq!(snap(s, 8), want, "{s}");
        }
        for k in -100_000..100_000 {
            let s = k as f32 * 0.013_7;
            assert_eq!(snap(s, 8), (s * 256.0).round_ties_even() as i64, "{s}");
            assert_eq!(snap(s, 12), snap(s, 8), "{s}");
            assert_eq!(snap(s, 2), (s * 4.0).round_ties_even() as i64 * 64, "{s}");
            assert_eq!(snap(s, 0), s.round_ties_even() as i64 * 256, "{s}");
        }
        assert_eq!(snap(f32::NAN, 8), 0);
        assert_eq!(snap(1e30, 8), 1 << 23);
        assert_eq!(snap(f32::NAN, 3), 0);
        assert_eq!(snap(1e30, 3), 1 << 23);
        assert_eq!(snap(-1e30, 0), -(1 << 23));
    }

    #[test]
    fn ccw_is_front_and_edges_positive_inside() {
        let (a, b, c) = (cv(-0.5, -0.5), cv(0.5, -0.5), cv(0.0, 0.5));
        let t = run([&a, &b, &c], 64, 64, Cull::Back).unwrap();
        assert!(t.info.front);
        let (px, py) = (32 * ONE + HALF, 32 * ONE + HALF);
        for k in 0..3 {
            let (a, b) = t.ab(k);
            assert!(a * px + b * py + t.c[k] > 0);
        }
        assert_eq!(
            run([&a, &c, &b], 64, 64, Cull::Back).unwrap_err(),
            Reject::Backface
        );
    }

    #[test]
    fn bounds_are_pixel_centres_inside_the_box() {
        // Box from x = 1.5 px to 3.5 px covers centres of pixels 1, 2, 3.
        let s = |p: f32| p / 4.0 - 1.0;
        let (a, b, c) = (
            cv(s(1.5), -s(1.5)),
            cv(s(3.5), -s(1.5)),
            cv(s(1.5), -s(3.5)),
        );
        let t = run([&a, &b, &c], 8, 8, Cull::None).unwrap();
        assert_eq!((t.x0, t.x1, t.y0, t.y1), (1, 3, 1, 3));
    }
}
