//! The environment's reads for eight shaded points at once: where the taps fall, their
//! weights and the blends are lane arithmetic; only the texel loads go lane by lane. The
//! results are those of the one-point reads ([`Plane::bilinear`], the chain's levels, the
//! BRDF table) bit for bit wherever the coordinates are finite: the same operations in the
//! same order, never fused.
//!
//! Measured on the bunny on the ground (`realist bench frame --shading pbr --ground`, 2
//! threads, Intel Xeon with AVX-512, 2026-11-29): the ambient stage, which reads the
//! specular chain twice, the irradiance once and the BRDF table once per point, took 58 %
//! of the frame with those reads made one lane at a time, most of it in the branches of
//! the index arithmetic.

use realist_simd::{Level, F8, I8, LANES};

use super::equirect::Plane;

/// `|x|` beyond which a texel coordinate is clamped before its floor (exact below 2^22).
const COORD_LIMIT: f32 = 4_194_304.0;

/// `a (1 - t) + b t`, as glam's `lerp` (not fused, so the lanes match the scalar reads).
#[inline(always)]
fn lerp<L: Level>(a: F8<L>, b: F8<L>, t: F8<L>) -> F8<L> {
    a * (F8::splat(1.0) - t) + b * t
}

/// Eight bilinear reads of planes whose size may differ by lane: each tap's texel index
/// (top left, top right, bottom left, bottom right) and the two weights. `u` wraps (one
/// period either way, as the image coordinates of a direction need; then clamped), `v`
/// clamps, as [`Plane::bilinear`].
struct Taps<L: Level> {
    at: [[i32; LANES]; 4],
    tx: F8<L>,
    ty: F8<L>,
}

#[inline(always)]
fn taps<L: Level>(u: F8<L>, v: F8<L>, w: I8<L>, h: I8<L>) -> Taps<L> {
    let fx = u * w.to_f32() - F8::splat(0.5);
    let fy = v * h.to_f32() - F8::splat(0.5);
    let x0 = fx.clamp(-COORD_LIMIT, COORD_LIMIT).floor();
    let y0 = fy.clamp(-COORD_LIMIT, COORD_LIMIT).floor();
    let (tx, ty) = (fx - x0, fy - y0);
    let (zero, one) = (I8::splat(0), I8::splat(1));
    let xi = x0.to_int();
    let xi = I8::select(xi.lt(zero), xi + w, xi);
    let xi = I8::select(xi.lt(w), xi, xi - w).clamp0(w - one);
    let x1 = I8::select((xi + one).eq(w), zero, xi + one);
    let yi = y0.to_int();
    let (row0, row1) = (yi.clamp0(h - one) * w, (yi + one).clamp0(h - one) * w);
    Taps {
        at: [
            (row0 + xi).to_array(),
            (row0 + x1).to_array(),
            (row1 + xi).to_array(),
            (row1 + x1).to_array(),
        ],
        tx,
        ty,
    }
}

/// Bilinear RGB of lane `i`'s plane `planes[i]` at `(u, v)`.
#[inline(always)]
pub(super) fn bilinear<L: Level>(planes: [&Plane; LANES], u: F8<L>, v: F8<L>) -> [F8<L>; 3] {
    let (mut w, mut h) = ([0; LANES], [0; LANES]);
    for i in 0..LANES {
        (w[i], h[i]) = (planes[i].width as i32, planes[i].height as i32);
    }
    let t = taps(u, v, I8::from_array(w), I8::from_array(h));
    // [tap][channel][lane]
    let mut c = [[[0.0f32; LANES]; 3]; 4];
    for (i, plane) in planes.iter().enumerate() {
        for (k, at) in t.at.iter().enumerate() {
            let j = 3 * at[i] as usize;
            if let Some(s) = plane.rgb.get(j..j + 3) {
                c[k][0][i] = s[0];
                c[k][1][i] = s[1];
                c[k][2][i] = s[2];
            }
        }
    }
    blend(&c, t.tx, t.ty)
}

/// The bilinear blend of four taps' three values (`c[tap][value]`, taps as [`Taps::at`]).
/// No closures: lane code must inline into the kernel that calls it.
#[inline(always)]
fn blend<L: Level>(c: &[[[f32; LANES]; 3]; 4], tx: F8<L>, ty: F8<L>) -> [F8<L>; 3] {
    let mut out = [F8::ZERO; 3];
    for (ch, o) in out.iter_mut().enumerate() {
        let top = lerp(F8::from_array(c[0][ch]), F8::from_array(c[1][ch]), tx);
        let bottom = lerp(F8::from_array(c[2][ch]), F8::from_array(c[3][ch]), tx);
        *o = lerp(top, bottom, ty);
    }
    out
}

/// A chain's read at roughness `r` (bilinear in levels `⌊r (M-1)⌋` and the next, linear
/// between; NaN reads level 0), as the one-point `read_chain`. `levels` is not empty.
#[inline(always)]
pub(super) fn chain<L: Level>(levels: &[Plane], u: F8<L>, v: F8<L>, r: F8<L>) -> [F8<L>; 3] {
    let last = levels.len() - 1;
    // `clamp` takes NaN to 0.
    let f = r.clamp(0.0, 1.0) * last as f32;
    let k = f.to_int().min(I8::splat(last.saturating_sub(1) as i32));
    let t = f - k.to_f32();
    let ks = k.to_array();
    let mut at = [&levels[0]; LANES];
    for i in 0..LANES {
        at[i] = &levels[ks[i] as usize];
    }
    let mut a = bilinear(at, u, v);
    let next = t.gt(F8::ZERO);
    if next.bits() == 0 {
        return a;
    }
    for i in 0..LANES {
        at[i] = &levels[(ks[i] as usize + 1).min(last)];
    }
    let b = bilinear(at, u, v);
    for ch in 0..3 {
        a[ch] = F8::select(next, lerp(a[ch], b[ch], t), a[ch]);
    }
    a
}

/// The BRDF table's `(A, B, E_c)` bilinear at `(nv, r)` on a `size`² grid, as
/// `BrdfLut::lookup_ess` (NaN reads entry 0).
#[inline(always)]
pub(super) fn table<L: Level>(
    size: usize,
    ab: &[[f32; 2]],
    ec: &[f32],
    nv: F8<L>,
    r: F8<L>,
) -> [F8<L>; 3] {
    let last = (size - 1) as f32;
    let fx = nv.clamp(0.0, 1.0) * last;
    let fy = r.clamp(0.0, 1.0) * last;
    let cap = I8::splat(size as i32 - 2);
    let (x0, y0) = (fx.to_int().min(cap), fy.to_int().min(cap));
    let (tx, ty) = (fx - x0.to_f32(), fy - y0.to_f32());
    let (n, one) = (I8::splat(size as i32), I8::splat(1));
    let row0 = y0 * n + x0;
    let at = [
        row0.to_array(),
        (row0 + one).to_array(),
        (row0 + n).to_array(),
        (row0 + n + one).to_array(),
    ];
    // [tap][value][lane]
    let mut c = [[[0.0f32; LANES]; 3]; 4];
    for i in 0..LANES {
        for (k, at) in at.iter().enumerate() {
            let j = at[i] as usize;
            if let (Some(&[a, b]), Some(&e)) = (ab.get(j), ec.get(j)) {
                c[k][0][i] = a;
                c[k][1][i] = b;
                c[k][2][i] = e;
            }
        }
    }
    blend(&c, tx, ty)
}
