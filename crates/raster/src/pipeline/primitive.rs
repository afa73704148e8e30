//! Primitive assembly and binning: culling, clipping and set-up of one triangle, the tiles it touches, and the flush of a tile's triangles to the fill.

use super::*;

/// Culls, clips and sets up one input triangle, appending the results to `chunk` (and, with
/// `tiles_x`, to its tile lists: binned before the triangle is stored, while it is still
/// in registers).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn assemble(
    d: &Draw<'_>,
    pre: Option<&[PreVert]>,
    t: &[u32; 3],
    g: Vec2,
    vp: Viewport,
    tiles_x: Option<u32>,
    chunk: &mut Chunk,
) {
    let Chunk {
        tris: out,
        attrs,
        bins,
        stats: st,
    } = chunk;
    let stride = d.stride;
    // With per-vertex records a non-finite vertex is caught by them (not projected: the
    // triangle is degenerate) or before clipping; without, here. Tested by
    // `a_non_finite_vertex_culls_its_triangle_on_every_path`.
    let fetch = |i: u32| -> Option<(Vec4, &[f32])> {
        let p = d.clip.get(i as usize)?;
        let k = i as usize * stride;
        let v = d.varyings.get(k..k + stride)?;
        (pre.is_some() || p.is_finite()).then_some((*p, v))
    };
    let (Some(a), Some(b), Some(c)) = (fetch(t[0]), fetch(t[1]), fetch(t[2])) else {
        st.culled_degenerate += 1;
        return;
    };
    // Outcodes (and, inside the guard band, the projected vertices) computed once per
    // vertex when the pipeline did so, else here.
    let hw_hh = (vp.width as f32 * 0.5, vp.height as f32 * 0.5);
    let vert = |i: u32, p: Vec4| match pre.and_then(|pre| pre.get(i as usize)) {
        Some(v) => *v,
        None => PreVert::new(p, g, hw_hh.0, hw_hh.1, d.state.subpixel_bits),
    };
    let pv = [vert(t[0], a.0), vert(t[1], b.0), vert(t[2], c.0)];
    // Trivial reject against the real frustum; clipping needs against near/far and guard band.
    if pv[0].frustum & pv[1].frustum & pv[2].frustum != 0 {
        st.culled_frustum += 1;
        return;
    }
    // Section planes: culled when all three corners are on a removed side of one plane,
    // clipped when they straddle one.
    let planes = &d.sections[..d.sections.len().min(MAX_SECTIONS)];
    let cut = if planes.is_empty() {
        0
    } else {
        let c = [a.0, b.0, c.0].map(|p| section_code(p, planes));
        if c[0] & c[1] & c[2] != 0 {
            st.culled_section += 1;
            return;
        }
        c[0] | c[1] | c[2]
    };
    let need = pv[0].guard | pv[1].guard | pv[2].guard;
    if need == 0 && cut == 0 {
        let s = pv
            .iter()
            .all(|v| v.projected)
            .then(|| [pv[0].screen(), pv[1].screen(), pv[2].screen()]);
        let _ = push(
            d,
            vp,
            tiles_x,
            (out, attrs, bins),
            s,
            [a.1, b.1, c.1],
            None,
            st,
        );
        return;
    }
    // Not finite: culled here, as without per-vertex records, not counted as clipped.
    if !(a.0.is_finite() && b.0.is_finite() && c.0.is_finite()) {
        st.culled_degenerate += 1;
        return;
    }
    st.clipped += 1;
    // The orientation every piece must keep: the sign of det[X; Y; W] of the whole triangle
    // (homogeneous rasterization: positive = counter-clockwise in NDC where w > 0).
    let det = homogeneous_orientation(a.0, b.0, c.0);
    if det == 0.0 || !det.is_finite() {
        st.culled_degenerate += 1;
        return;
    }
    let ccw = Some(det > 0.0);
    // Clip against every violated plane (near first: it guarantees w > 0 afterwards).
    let tri = [a, b, c].map(|(p, v)| ClipVertex::new(p, v));
    let mut poly = clip_polygon(Poly::triangle(tri, stride), need, g);
    if cut != 0 {
        poly = clip_sections(poly, planes, cut);
    }
    let poly = poly.as_slice();
    if poly.len() < 3 {
        st.culled_frustum += 1;
        return;
    }
    let mut rejected = Stats::default();
    let mut any = false;
    let (hw, hh) = hw_hh;
    for i in 1..poly.len() - 1 {
        let c = Corners::of([&poly[0], &poly[i], &poly[i + 1]], stride);
        let s = project3(c.pos, hw, hh, d.state.subpixel_bits);
        any |= push(
            d,
            vp,
            tiles_x,
            (out, attrs, bins),
            s,
            c.var,
            ccw,
            &mut rejected,
        );
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

/// Sets up one projected triangle (or piece) of draw `d` and appends it to the chunk's
/// `(tris, attrs, bins)`, binned while it is still in registers; counts a rejection into
/// `st`. True if it was kept. A function, not a closure: the closure was compiled out of
/// line, without the kernel's features (a fifth of a frame of small triangles).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn push(
    d: &Draw<'_>,
    vp: Viewport,
    tiles_x: Option<u32>,
    (out, attrs, bins): (&mut Vec<SetupTri>, &mut Vec<f32>, &mut [Vec<u16>]),
    s: Option<[ScreenVert; 3]>,
    var: [&[f32]; 3],
    ccw: Option<bool>,
    st: &mut Stats,
) -> bool {
    let set = match s {
        Some(s) => setup_projected(s, var, vp, d.id, d.state, ccw, attrs),
        None => Err(Reject::Degenerate),
    };
    match set {
        Ok(s) => {
            if let Some(tx) = tiles_x {
                bin(tx, vp.reach, &s, out.len() as u16, bins);
            }
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
    }
}

/// det[X; Y; W] of a clip-space triangle, in f64: its sign is the orientation of the
/// triangle's visible (w > 0) part in NDC, positive for counter-clockwise.
pub(super) fn homogeneous_orientation(a: Vec4, b: Vec4, c: Vec4) -> f64 {
    let [a, b, c] = [a, b, c].map(|p| [f64::from(p.x), f64::from(p.y), f64::from(p.w)]);
    a[0] * (b[1] * c[2] - c[1] * b[2]) - b[0] * (a[1] * c[2] - c[1] * a[2])
        + c[0] * (a[1] * b[2] - b[1] * a[2])
}

/// Appends triangle `index` to the list of every tile its bounds touch and its edges do not
/// exclude (a tile is excluded when one edge is negative at all four corners of the box of
/// its sample points: its pixel centres widened by `reach`, see [`Viewport::reach`]).
#[inline(always)]
pub(crate) fn bin(tiles_x: u32, reach: i64, t: &SetupTri, index: u16, bins: &mut [Vec<u16>]) {
    let (tx0, ty0, tx1, ty1) = (t.x0 / TILE, t.y0 / TILE, t.x1 / TILE, t.y1 / TILE);
    let single = tx0 == tx1 && ty0 == ty1;
    for ty in ty0..=ty1 {
        for tx in tx0..=tx1 {
            if !single && tile_outside(t, reach, tx * TILE, ty * TILE) {
                continue;
            }
            bins[(ty * tiles_x + tx) as usize].push(index);
        }
    }
}

pub(super) fn tile_outside(t: &SetupTri, reach: i64, x: u32, y: u32) -> bool {
    use crate::setup::ONE;
    let (px, py) = (
        i64::from(x) * ONE + ONE / 2 - reach,
        i64::from(y) * ONE + ONE / 2 - reach,
    );
    let span = i64::from(TILE - 1) * ONE + 2 * reach;
    (0..3).any(|k| {
        let (a, b) = t.ab(k);
        let e = a * px + b * py + t.c[k] + t.bias(k);
        e + (a * span).max(0) + (b * span).max(0) < 0
    })
}

thread_local! {
    /// Each worker's fill counters, visibility buffer and batches ([`flush`]).
    static FILL: RefCell<Option<Box<FillScratch>>> = const { RefCell::new(None) };
}

/// Fills every tile with its binned triangles (in parallel over tiles, in chunk order).
/// Tiles are skipped once `stop` answers true; returns false if any was.
pub(crate) fn flush(
    target: &mut Target,
    chunks: &[Chunk],
    bins: &mut Bins,
    shader: &dyn FragmentShader,
    stats: &mut Stats,
    stop: &(dyn Fn() -> bool + Sync),
) -> bool {
    let start = Instant::now();
    let fns = FillFns::pick(bins.kernel);
    let (tiles, shaded, rejected, calls, skipped) = target
        .tiles
        .par_iter_mut()
        .zip(bins.costs[..bins.active].par_iter_mut())
        .enumerate()
        .filter(|(t, _)| chunks.iter().any(|c| !c.bins[*t].is_empty()))
        .map(|(index, (tile, cost))| {
            if stop() {
                return (0, 0, 0, 0, 1);
            }
            let start = Instant::now();
            tile.materialize();
            // The worker's counters, visibility buffer and batches: allocated once per
            // thread, not per frame (the renderer allocates nothing after its first frame).
            let mut run = |n: &mut FillScratch| {
                (fns.tile)(&fns, tile, index, chunks, shader, n);
                (n.shaded, n.depth_rejected, n.calls)
            };
            let (shaded, rejected, calls) = FILL.with(|cell| match cell.try_borrow_mut() {
                Ok(mut n) => run(n.get_or_insert_with(Box::default)),
                // Never while a tile is filled on this thread (nothing in it yields to
                // rayon); a fresh set if it ever were.
                Err(_) => run(&mut FillScratch::default()),
            });
            cost.nanos += start.elapsed().as_nanos() as u64;
            cost.fragments += shaded;
            (1, shaded, rejected, calls, 0)
        })
        .reduce(
            || (0, 0, 0, 0, 0),
            |a, b| (a.0 + b.0, a.1 + b.1, a.2 + b.2, a.3 + b.3, a.4 + b.4),
        );
    stats.tiles += tiles;
    stats.pixels_shaded += shaded;
    stats.depth_rejected += rejected;
    stats.shader_calls += calls;
    bins.fill_nanos += start.elapsed().as_nanos() as u64;
    skipped == 0
}
