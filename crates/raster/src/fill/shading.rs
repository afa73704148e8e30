//! Shading the visibility buffer (the resolve), the per-row masks and depth tests, perspective-correct interpolation into a group's lanes, the colour writes with blending, and the analytic derivatives.

use super::*;

crate::simd::per_kernel! {
    /// Shades the deferred fragments of the tile (see the module docs): each group of eight
    /// pixels with a live lane, triangle by triangle, interpolated into the open batch of
    /// its draw and facing; a batch is shaded when it has no room for another group, and
    /// all of them at the end.
    pub(super) fn resolve<L>(tile: &mut Tile, chunks: &[Chunk], shader: &dyn FragmentShader, n: &mut FillScratch) {
        resolve_body::<L>(tile, chunks, shader, n);
    }
}

#[inline(always)]
pub(super) fn resolve_body<L: Level>(
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
pub(super) fn open_batch<L: Level>(
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
pub(super) fn flush_deferred<L: Level>(
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
pub(super) fn same<L: Level>(t: &[u32], id: u32) -> u32 {
    I8::<L>::load_u32(t).eq(I8::splat(id as i32)).bits()
}

/// Lanes of a row whose (biased) edge values at lane 0 are `row` that lie inside all three
/// edges: bit `i` for lane `i` (bits above the eighth are set; the caller masks them).
#[inline(always)]
pub(super) fn row_mask(r: &Rows<'_>, row: [i64; 3]) -> u32 {
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
pub(super) fn depth_pass<L: Level>(test: DepthTest, z: F8<L>, depth: &[f32]) -> u32 {
    let depth = F8::load(depth);
    match test {
        DepthTest::Greater => z.gt(depth).bits(),
        DepthTest::GreaterEqual => z.ge(depth).bits(),
        DepthTest::Always => u32::MAX,
    }
}

/// The perspective weights `[p_1, p_2, 1 / D]` of `tri` at screen-space barycentrics `l`.
#[inline(always)]
pub(super) fn perspective<L: Level>(tri: &SetupTri, l: [F8<L>; 3]) -> [F8<L>; 3] {
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
    pub(super) var: &'a mut [Lane; MAX_VARYINGS],
    pub(super) ddx: &'a mut [Lane; MAX_VARYINGS],
    pub(super) ddy: &'a mut [Lane; MAX_VARYINGS],
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
pub(super) fn store_color<L: Level>(color: &mut [f32], o: usize, keep: u32, out: &Colors) {
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
pub(super) fn write<L: Level>(
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
pub(super) fn blend<L: Level>(mode: Blend, keep: M8<L>, out: &Colors, dst: [&mut [f32]; 4]) {
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
    pub(super) cx: [f32; 2],
    pub(super) cy: [f32; 2],
    /// `∂D/∂x`, `∂D/∂y`.
    pub(super) dx: f32,
    pub(super) dy: f32,
}

impl Gradients {
    #[inline(always)]
    pub(super) fn new(tri: &SetupTri) -> Self {
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
    pub(super) fn weights<L: Level>(&self, p1: F8<L>, p2: F8<L>, inv: F8<L>) -> [F8<L>; 4] {
        let f = |c: f32, p: F8<L>, d: f32| mad(p, F8::splat(-d), F8::splat(c)) * inv;
        [
            f(self.cx[0], p1, self.dx),
            f(self.cx[1], p2, self.dx),
            f(self.cy[0], p1, self.dy),
            f(self.cy[1], p2, self.dy),
        ]
    }
}
