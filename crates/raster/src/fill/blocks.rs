//! The fill of one triangle's rows: the per-triangle row constants and varyings, the 8x8 block walk (single- and multisampled), the small-triangle path, the direct-colour and forward fills.

use super::*;

/// The per-triangle constants of `tri`'s rows in `tile`, or `None` if it has no pixel there
/// or its varyings are missing.
#[inline(always)]
pub(super) fn rows<'a>(
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
pub(super) fn varyings<'a>(
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

pub(super) enum Coverage {
    None,
    Partial,
    Full,
}

/// `[f(0), f(1), f(2)]`, written out: `[0, 1, 2].map(f)` in the per-triangle set-up of a
/// tile was compiled out of line (`array::try_map`, 4-5% of a frame of small triangles).
#[inline(always)]
pub(super) fn map3<T>(mut f: impl FnMut(usize) -> T) -> [T; 3] {
    [f(0), f(1), f(2)]
}

/// Edge function (biased) at the centre of pixel (x, y).
#[inline(always)]
pub(super) fn edge_at(tri: &SetupTri, k: usize, x: u32, y: u32) -> i64 {
    let (a, b) = tri.ab(k);
    a * (i64::from(x) * ONE + HALF) + b * (i64::from(y) * ONE + HALF) + tri.c[k] + tri.bias(k)
}

/// Coverage of the pixels `x0..=x1` by `y0..=y1`: the extremes of each edge over the box of
/// their sample points (the pixel centres widened by `reach` fixed units on every side).
#[inline(always)]
pub(super) fn classify(tri: &SetupTri, reach: i64, x0: u32, y0: u32, x1: u32, y1: u32) -> Coverage {
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
pub(super) fn block<L: Level, const TEST: bool, const MODE: u8>(
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
pub(super) const DEFER: u8 = 0;
pub(super) const DIRECT: u8 = 1;
pub(super) const FORWARD: u8 = 2;
pub(super) const DEPTH: u8 = 3;

/// Counters of a triangle's fill, kept in registers and added to the tile's at its end.
#[derive(Clone, Copy, Default)]
pub(super) struct Counts {
    pub(super) rejected: u32,
    pub(super) shaded: u32,
    pub(super) calls: u32,
}

impl Counts {
    #[inline(always)]
    pub(super) fn add_to(self, n: &mut FillScratch) {
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
pub(super) fn block_ms<L: Level, const TEST: bool>(
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
pub(super) fn record<L: Level>(vis: &mut Vis, o: usize, live: u32, id: TriId) {
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
pub(super) fn small_bounds(tile: &Tile, r: &Rows<'_>) -> Option<(u32, u32, u32, u32)> {
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
pub(super) fn small<L: Level, const MODE: u8>(
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
pub(super) fn direct<L: Level>(
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
pub(super) fn push_forward<L: Level>(
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
pub(super) fn shade_forward<L: Level>(
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
