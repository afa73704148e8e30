//! Eight-lane sampling: [`Texture::sample_lanes`] and [`Texture::sample_grad_lanes`], the
//! lane versions of [`Texture::sample_with`] and [`Texture::sample_grad_with`] for shaders
//! that work on eight pixels at a time (see [`crate::simd::lanes`]).
//!
//! Everything but the texel reads and the filtering is done on all lanes at once: folding
//! the UV for the wrap modes, the level of detail (with [`F8::log2`]; for anisotropic
//! filtering also the taps per lane, whose positions are lanes too: one filter call per
//! tap for the lanes that have it), the level of each
//! lane and its size, texel coordinates (floors and wraps in integer lanes) and bilinear
//! weights. The texel reads, their decoding and the weighting are a loop over the live
//! lanes on four-channel texels: base texels are decoded by table, and the levels below
//! are 16-bit linear RGBA in one array (see `mip.rs`), so a lane's level changes only its
//! index. Every helper is `#[inline(always)]` and generic over the lane level, so in a
//! kernel's function it compiles to that kernel's vector instructions, and nothing here
//! calls libm (floors are the level's, remainders are exact subtractions).
//!
//! Results equal the scalar sampler's: the arithmetic is the same operation for operation
//! (no fused multiply-add), except the logarithm of the level of detail, a polynomial here
//! (error about 1e-7) against libm's `log2f`. Nearest and bilinear samples are therefore
//! bit-identical, trilinear and anisotropic ones equal within about 1e-6 (the blend between levels is
//! continuous in the level of detail); the tests compare them on random and degenerate
//! inputs for every kernel the machine has.

// Lane loops index several arrays by the lane number on purpose.
#![allow(clippy::needless_range_loop)]

use super::mip::{self, ChainTexels, U16_MAX};
use super::{linear_table, srgb_table, Filter, Sampler, Texels, Texture, Wrap};
use crate::simd::{Level, F8, I8, LANES, M8};

/// 2^23: floats at least this large are integers.
const INTEGRAL: f32 = 8_388_608.0;

/// `trunc` of every lane (the sign kept, so -0.5 gives -0, as `f32::trunc`); lanes of at
/// least 2^23 in magnitude are whole already and kept.
#[inline(always)]
fn trunc<L: Level>(x: F8<L>) -> F8<L> {
    let sign = I8::splat(i32::MIN);
    let t = F8::from_bits(x.to_int().to_f32().bits() | (x.bits() & sign));
    F8::select(x.abs().lt(F8::splat(INTEGRAL)), t, x)
}

/// Largest |x| [`floor_i`] handles: 2^22.
const COORD_LIMIT: f32 = 4_194_304.0;

/// `floor` of texel coordinates as integers, exact for |x| < 2^22 (coordinates beyond are
/// clamped there first; NaN reads as -2^22).
#[inline(always)]
fn floor_i<L: Level>(x: F8<L>) -> I8<L> {
    x.clamp(-COORD_LIMIT, COORD_LIMIT).floor().to_int()
}

/// Lanes where `x` is finite.
#[inline(always)]
fn finite<L: Level>(x: F8<L>) -> u32 {
    x.abs().lt(F8::splat(f32::INFINITY)).bits()
}

/// [`super::reduce`] on lanes of finite coordinates.
#[inline(always)]
fn reduce<L: Level>(t: F8<L>, wrap: Wrap) -> F8<L> {
    match wrap {
        Wrap::Repeat => t - t.floor(),
        Wrap::MirroredRepeat => {
            // t % 2 (exact: t / 2 is exact, twice its truncation is representable, and the
            // difference of two floats this close is exact), then made non-negative.
            let r = t - trunc(t * 0.5) * 2.0;
            F8::select(r.lt(F8::ZERO), r + 2.0, r)
        }
        Wrap::ClampToEdge => t.clamp(-1.0, 2.0),
    }
}

/// [`super::fold`] on lanes: a lane with a non-finite coordinate reads (0, 0).
#[inline(always)]
fn fold<L: Level>(u: F8<L>, v: F8<L>, s: Sampler) -> (F8<L>, F8<L>) {
    let ok = M8::from_bits(finite(u) & finite(v));
    let (u, v) = (F8::select(ok, u, F8::ZERO), F8::select(ok, v, F8::ZERO));
    (reduce(u, s.wrap_u), reduce(v, s.wrap_v))
}

/// [`super::wrap_index`] on lanes: integer texel coordinates `i` of folded UVs (so within
/// a period or two of the image: -n - 1 ..= 2n) into `0..n`, per-lane `n`. The result is
/// clamped to `0..n` in every mode, whatever `i` is.
#[inline(always)]
fn wrap_index<L: Level>(i: I8<L>, n: I8<L>, wrap: Wrap) -> I8<L> {
    let zero = I8::splat(0);
    let last = n - I8::splat(1);
    let r = match wrap {
        Wrap::ClampToEdge => i,
        Wrap::Repeat => {
            let i = I8::select(i.lt(zero), i + n, i);
            I8::select(n.gt(i), i, i - n)
        }
        Wrap::MirroredRepeat => {
            let p = n + n;
            let i = I8::select(i.lt(zero), i + p, i);
            let i = I8::select(p.gt(i), i, i - p);
            I8::select(n.gt(i), i, p - I8::splat(1) - i)
        }
    };
    r.clamp0(last)
}

/// `a * (1 - t) + b * t` per channel, as glam's `Vec4::lerp`.
#[inline(always)]
fn lerp4(a: [f32; 4], b: [f32; 4], t: f32) -> [f32; 4] {
    let s = 1.0 - t;
    [
        a[0] * s + b[0] * t,
        a[1] * s + b[1] * t,
        a[2] * s + b[2] * t,
        a[3] * s + b[3] * t,
    ]
}

/// Where a lane filter reads texels: the base level in one of its storages, or the levels
/// below it. `texel(i)` is texel `i` in linear light with the operations of the scalar
/// [`Texture::fetch`] (or [`super::mip::unpack`]); an index outside reads zero (never made:
/// the coordinates are wrapped or clamped).
trait Source: Copy {
    fn texel(self, i: i32) -> [f32; 4];
}

/// 8-bit texels decoded by two tables (sRGB or linear for RGB, linear for alpha).
#[derive(Clone, Copy)]
struct Bytes<'a> {
    texels: &'a [[u8; 4]],
    rgb: &'a [f32; 256],
    alpha: &'a [f32; 256],
}

impl Source for Bytes<'_> {
    #[inline(always)]
    fn texel(self, i: i32) -> [f32; 4] {
        let t = self
            .texels
            .get(i as u32 as usize)
            .copied()
            .unwrap_or_default();
        [
            self.rgb[t[0] as usize],
            self.rgb[t[1] as usize],
            self.rgb[t[2] as usize],
            self.alpha[t[3] as usize],
        ]
    }
}

/// 16-bit linear texels.
#[derive(Clone, Copy)]
struct Shorts<'a>(&'a [[u16; 4]]);

impl Source for Shorts<'_> {
    #[inline(always)]
    fn texel(self, i: i32) -> [f32; 4] {
        let t = self.0.get(i as u32 as usize).copied().unwrap_or_default();
        t.map(|c| f32::from(c) * (1.0 / U16_MAX))
    }
}

/// 16-bit linear texels packed into a `u64` (the mip chain, see [`super::mip::ChainTexels`]).
#[derive(Clone, Copy)]
struct Packed<'a>(&'a [u64]);

impl Source for Packed<'_> {
    #[inline(always)]
    fn texel(self, i: i32) -> [f32; 4] {
        let t = self.0.get(i as u32 as usize).copied().unwrap_or(0);
        let k = 1.0 / U16_MAX;
        // Through the bytes: the compiler then reads the four channels as one vector
        // (shifts per channel were rebuilt with an insert per channel).
        let b = t.to_le_bytes();
        let c = [
            u16::from_le_bytes([b[0], b[1]]),
            u16::from_le_bytes([b[2], b[3]]),
            u16::from_le_bytes([b[4], b[5]]),
            u16::from_le_bytes([b[6], b[7]]),
        ];
        [
            f32::from(c[0]) * k,
            f32::from(c[1]) * k,
            f32::from(c[2]) * k,
            f32::from(c[3]) * k,
        ]
    }
}

/// Float texels.
#[derive(Clone, Copy)]
struct Floats<'a>(&'a [[f32; 4]]);

impl Source for Floats<'_> {
    #[inline(always)]
    fn texel(self, i: i32) -> [f32; 4] {
        self.0.get(i as u32 as usize).copied().unwrap_or_default()
    }
}

/// Where the four texels of a bilinear footprint are, per lane, and their weights: the
/// level-free form the (scalar, per-lane) texel reads take.
#[derive(Clone, Copy)]
struct Footprint {
    /// Each lane's level (0 = the base).
    level: [i32; LANES],
    /// Indices of texels (x0, y0), (x1, y0), (x0, y1), (x1, y1) of each lane's level: into
    /// the base's texels on level 0, into [`super::mip::Chain::texels`] below.
    idx: [[i32; LANES]; 4],
    tx: [f32; LANES],
    ty: [f32; LANES],
}

/// The four texels of a footprint, filtered (the same operations as the scalar
/// `bilinear`).
#[inline(always)]
fn bilinear(c: [[f32; 4]; 4], tx: f32, ty: f32) -> [f32; 4] {
    let top = lerp4(c[0], c[1], tx);
    let bottom = lerp4(c[2], c[3], tx);
    lerp4(top, bottom, ty)
}

/// Lane `i` of footprint `f`, filtered, from the base `base` or the levels below `mips`.
#[inline(always)]
fn footprint_sample<B: Source, M: Source>(base: B, mips: M, f: &Footprint, i: usize) -> [f32; 4] {
    let [a, b, c, d] = f.idx.map(|x| x[i]);
    let texels = if f.level[i] == 0 {
        [base.texel(a), base.texel(b), base.texel(c), base.texel(d)]
    } else {
        [mips.texel(a), mips.texel(b), mips.texel(c), mips.texel(d)]
    };
    bilinear(texels, f.tx[i], f.ty[i])
}

/// Filters footprint `a` of each lane in `mask`, and where `blend` = `(b, t, lanes)` has a
/// lane, blends it towards footprint `b` by `t`: per live lane, on four-channel texels.
/// Deferred shading fills the rows (7.8 live lanes of 8 on the peer's textured cow), but
/// eight-lane reads with AVX2 gathers (`vpgatherdd` for the texels and the decode tables)
/// measured slower than this loop on the AMD EPYC (Zen 4) machine: textured cow 14.6 to
/// 15.6 ms on one thread (2026-11-28). Lanes outside `mask` are zero. Channels out, one
/// array each.
#[inline(always)]
fn filter<B: Source, M: Source>(
    base: B,
    mips: M,
    a: &Footprint,
    blend: Option<(&Footprint, &[f32; LANES], u32)>,
    mask: u32,
) -> [[f32; LANES]; 4] {
    let mut out = [[0.0f32; LANES]; 4];
    let mut bits = mask & ((1 << LANES) - 1);
    while bits != 0 {
        let i = bits.trailing_zeros() as usize;
        bits &= bits - 1;
        let mut c = footprint_sample(base, mips, a, i);
        if let Some((b, t, lanes)) = blend {
            if lanes >> i & 1 != 0 {
                c = lerp4(c, footprint_sample(base, mips, b, i), t[i]);
            }
        }
        for ch in 0..4 {
            out[ch][i] = c[ch];
        }
    }
    out
}

impl Texture {
    /// Filters `fp` from this texture's base level and `chain` (the levels below; `None`
    /// when every lane is on the base). The one place the storage is matched: each storage
    /// kind is one instantiation of [`filter`] (8-bit sRGB and 8-bit linear differ only by a
    /// table). Not inlined, and not generic over the lane level: the texel reads are a
    /// scalar loop over the live lanes whatever the instruction set, so one copy serves
    /// every kernel and every shader.
    #[inline(never)]
    fn filter_any(
        &self,
        chain: Option<&mip::Chain>,
        a: &Footprint,
        blend: Option<(&Footprint, &[f32; LANES], u32)>,
        mask: u32,
    ) -> [[f32; LANES]; 4] {
        let (packed, floats): (&[u64], &[[f32; 4]]) = match chain.map(|c| &c.texels) {
            Some(ChainTexels::Unorm16(m)) => (m, &[]),
            Some(ChainTexels::Float(m)) => (&[], m),
            None => (&[], &[]),
        };
        match &self.texels {
            Texels::Srgb8(texels) | Texels::Linear8(texels) => {
                let rgb = if self.is_srgb() {
                    srgb_table()
                } else {
                    linear_table()
                };
                let base = Bytes {
                    texels,
                    rgb,
                    alpha: linear_table(),
                };
                filter(base, Packed(packed), a, blend, mask)
            }
            Texels::Linear16(texels) => filter(Shorts(texels), Packed(packed), a, blend, mask),
            Texels::Float(texels) => filter(Floats(texels), Floats(floats), a, blend, mask),
        }
    }

    /// [`Texture::filter_any`] with lanes out.
    #[inline(always)]
    fn filter_lanes<L: Level>(
        &self,
        chain: Option<&mip::Chain>,
        a: &Footprint,
        blend: Option<(&Footprint, &[f32; LANES], u32)>,
        mask: u32,
    ) -> [F8<L>; 4] {
        let [r, g, b, a] = self.filter_any(chain, a, blend, mask);
        [
            F8::from_array(r),
            F8::from_array(g),
            F8::from_array(b),
            F8::from_array(a),
        ]
    }

    /// The base-level footprint of a nearest or bilinear sample at folded UVs.
    #[inline(always)]
    fn base_footprint<L: Level>(&self, u: F8<L>, v: F8<L>, s: Sampler) -> Footprint {
        match s.filter {
            Filter::Nearest => {
                let (w, h) = (self.width as i32, self.height as i32);
                let x = floor_i(u * self.width as f32);
                let y = floor_i(v * self.height as f32);
                let x = wrap_index(x, I8::splat(w), s.wrap_u);
                let y = wrap_index(y, I8::splat(h), s.wrap_v);
                let i = (y * I8::splat(w) + x).to_array();
                // Weights 0: the texel alone, exactly (a * 1 + b * 0).
                Footprint {
                    level: [0; LANES],
                    idx: [i; 4],
                    tx: [0.0; LANES],
                    ty: [0.0; LANES],
                }
            }
            Filter::Bilinear | Filter::Trilinear | Filter::Anisotropic(_) => {
                let size = (self.width, self.height);
                footprint(size, &[0; 32], I8::default(), u, v, s)
            }
        }
    }

    /// [`Texture::sample_with`] on eight lanes (UVs `u`, `v`): RGBA in linear light, one
    /// [`F8`] per channel, zero on the lanes not set in `mask` (bit i = lane i). Equal to
    /// the scalar sample of each lane (see the module docs).
    #[must_use]
    #[inline(always)]
    pub fn sample_lanes<L: Level>(&self, u: F8<L>, v: F8<L>, mask: u32, s: Sampler) -> [F8<L>; 4] {
        self.sample_impl(u, v, None, mask, s)
    }

    /// [`Texture::sample_grad_with`] on eight lanes: UVs `u`, `v` and their screen-space
    /// derivatives per pixel along x (`dudx`, `dvdx`) and y (`dudy`, `dvdy`), which choose
    /// each lane's level of detail for [`Filter::Trilinear`]; the other filters ignore them
    /// (as [`Texture::sample_lanes`]). Lanes not set in `mask` are zero.
    #[must_use]
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub fn sample_grad_lanes<L: Level>(
        &self,
        u: F8<L>,
        v: F8<L>,
        dudx: F8<L>,
        dvdx: F8<L>,
        dudy: F8<L>,
        dvdy: F8<L>,
        mask: u32,
        s: Sampler,
    ) -> [F8<L>; 4] {
        self.sample_impl(u, v, Some([dudx, dvdx, dudy, dvdy]), mask, s)
    }

    /// Both lane samplers: derivatives `d` (`[dudx, dvdx, dudy, dvdy]`) choose the level of
    /// a trilinear sample and the taps of an anisotropic one; without them, or for the
    /// other filters, the base level is read.
    #[inline(always)]
    fn sample_impl<L: Level>(
        &self,
        u: F8<L>,
        v: F8<L>,
        d: Option<[F8<L>; 4]>,
        mask: u32,
        s: Sampler,
    ) -> [F8<L>; 4] {
        let top = (self.levels() - 1) as f32;
        let mipmapped = match d {
            Some(d) if s.filter.mipmapped() && top > 0.0 => Some(d),
            _ => None,
        };
        let Some([dudx, dvdx, dudy, dvdy]) = mipmapped else {
            let (u, v) = fold(u, v, s);
            return self.filter_lanes(None, &self.base_footprint(u, v, s), None, mask);
        };
        let chain = self.mips();
        let lod = self.lod_lanes(dudx, dvdx, dudy, dvdy);
        let Filter::Anisotropic(max) = s.filter else {
            let (u, v) = fold(u, v, s);
            return self.trilinear(chain, u, v, &Levels::new(lod, top), mask, s);
        };
        // As `sample_grad_with`: lanes with one tap are the trilinear sample (level `lod`
        // at the UV itself); the others average their taps along the major axis.
        let a = self.aniso_lanes([dudx, dvdx, dudy, dvdy], super::aniso_ratio(max));
        let single = M8::from_bits(a.single);
        let levels = Levels::new(F8::select(single, lod, a.lod), top);
        let taps = a.taps.to_array();
        let most = (0..LANES)
            .filter(|&i| mask >> i & 1 != 0)
            .map(|i| taps[i])
            .max()
            .unwrap_or(1);
        let n = a.taps.to_f32();
        let mut sum = [F8::ZERO; 4];
        for i in 0..most {
            let lanes = mask & a.taps.gt(I8::splat(i)).bits();
            let k = F8::splat(i as f32 + 0.5) / n - F8::splat(0.5);
            let tu = F8::select(single, u, u + a.axis[0] * k);
            let tv = F8::select(single, v, v + a.axis[1] * k);
            let (tu, tv) = fold(tu, tv, s);
            let c = self.trilinear(chain, tu, tv, &levels, lanes, s);
            for (acc, c) in sum.iter_mut().zip(c) {
                *acc += c;
            }
        }
        let inv = F8::ONE / n;
        sum.map(|c| c * inv)
    }

    /// A trilinear sample of each lane in `mask` at folded UVs and levels `l` (as
    /// `sample_lod_with`: bilinear on level floor(lod), blended towards the next level by
    /// the fraction where it is not zero; lod <= 0 is level 0 with no fraction).
    #[inline(always)]
    fn trilinear<L: Level>(
        &self,
        chain: &mip::Chain,
        u: F8<L>,
        v: F8<L>,
        l: &Levels<L>,
        mask: u32,
        s: Sampler,
    ) -> [F8<L>; 4] {
        let a = footprint(chain.size[0], &chain.offset, l.d, u, v, s);
        let lanes = mask & l.blend;
        if lanes == 0 {
            return self.filter_lanes(Some(chain), &a, None, mask);
        }
        let b = footprint(chain.size[0], &chain.offset, l.next, u, v, s);
        let t = l.t.to_array();
        self.filter_lanes(Some(chain), &a, Some((&b, &t, lanes)), mask)
    }

    /// [`Texture::aniso`] on eight lanes: the taps (1 where the derivatives are not
    /// finite), the level of detail of the lanes with several taps (with [`F8::log2`]) and
    /// the major axis (zero on single-tap lanes).
    #[inline(always)]
    fn aniso_lanes<L: Level>(&self, d: [F8<L>; 4], max: u8) -> AnisoLanes<L> {
        let [dudx, dvdx, dudy, dvdy] = d;
        let ok = finite(dudx) & finite(dvdx) & finite(dudy) & finite(dvdy);
        let (w, h) = (self.width as f32, self.height as f32);
        let (xu, xv) = (dudx * w, dvdx * h);
        let (yu, yv) = (dudy * w, dvdy * h);
        let lx = (xu * xu + xv * xv).sqrt();
        let ly = (yu * yu + yv * yv).sqrt();
        let x_major = lx.ge(ly);
        let major = F8::select(x_major, lx, ly);
        let minor = F8::select(x_major, ly, lx);
        let (ma, mi) = (major.to_array(), minor.to_array());
        let mut taps = [1i32; LANES];
        for i in 0..LANES {
            if ok >> i & 1 != 0 {
                taps[i] = super::aniso_taps(ma[i], mi[i], max) as i32;
            }
        }
        let taps = I8::from_array(taps);
        let single = I8::splat(2).gt(taps).bits();
        let top = (self.levels() - 1) as f32;
        let lod = (major / taps.to_f32()).log2().clamp(0.0, top);
        let keep = M8::from_bits(!single);
        AnisoLanes {
            taps,
            single,
            lod,
            axis: [
                F8::select(keep, F8::select(x_major, dudx, dudy), F8::ZERO),
                F8::select(keep, F8::select(x_major, dvdx, dvdy), F8::ZERO),
            ],
        }
    }

    /// [`Texture::lod`] on eight lanes (with [`F8::log2`] for the logarithm).
    #[inline(always)]
    fn lod_lanes<L: Level>(&self, dudx: F8<L>, dvdx: F8<L>, dudy: F8<L>, dvdy: F8<L>) -> F8<L> {
        let ok = finite(dudx) & finite(dvdx) & finite(dudy) & finite(dvdy);
        let (w, h) = (self.width as f32, self.height as f32);
        let (xu, xv) = (dudx * w, dvdx * h);
        let (yu, yv) = (dudy * w, dvdy * h);
        let rho2 = (xu * xu + xv * xv).max(yu * yu + yv * yv);
        // log2(0) is a large negative number here (not -inf), clamped to 0 all the same.
        let lod = (rho2.log2() * 0.5).clamp(0.0, (self.levels() - 1) as f32);
        F8::select(M8::from_bits(ok), lod, F8::ZERO)
    }
}

/// The levels a trilinear sample reads, per lane: `d` = floor(lod), `next` = the level
/// below it (clamped to the last), `t` = the fraction, `blend` = the lanes where it is
/// not zero.
struct Levels<L: Level> {
    d: I8<L>,
    next: I8<L>,
    t: F8<L>,
    blend: u32,
}

impl<L: Level> Levels<L> {
    /// For levels of detail `lod` in [0, top] (as [`Texture::lod`] gives them).
    #[inline(always)]
    fn new(lod: F8<L>, top: f32) -> Self {
        let d = floor_i(lod);
        let t = lod - d.to_f32();
        Levels {
            d,
            next: (d + I8::splat(1)).clamp0(I8::splat(top as i32)),
            t,
            blend: t.gt(F8::ZERO).bits(),
        }
    }
}

/// [`super::AnisoTaps`] on eight lanes.
struct AnisoLanes<L: Level> {
    taps: I8<L>,
    /// Lanes with one tap (bit i = lane i).
    single: u32,
    lod: F8<L>,
    /// Major axis, u and v.
    axis: [F8<L>; 2],
}

/// The bilinear footprint of each lane's level `level` at folded UVs (the lane version of
/// the coordinates and weights of `super::bilinear`), for a base of `size` and levels
/// starting at `offset` (see [`super::mip::Chain`]; the base at 0).
#[inline(always)]
fn footprint<L: Level>(
    size: (u32, u32),
    offset: &[u32; 32],
    level: I8<L>,
    u: F8<L>,
    v: F8<L>,
    s: Sampler,
) -> Footprint {
    // Level sizes (each level halves each side, rounding down, to no less than 1) and the
    // first texel of each lane's level: one look-up when the lanes share their level (the
    // usual case), else one per lane.
    let levels = level.to_array();
    let l0 = levels[0];
    let side = |n: u32, l: i32| (n >> (l as u32 & 31)).max(1) as i32;
    let (w, h, first) = if levels.iter().all(|&l| l == l0) {
        (
            I8::splat(side(size.0, l0)),
            I8::splat(side(size.1, l0)),
            I8::splat(offset[l0 as usize & 31] as i32),
        )
    } else {
        (
            I8::from_array(levels.map(|l| side(size.0, l))),
            I8::from_array(levels.map(|l| side(size.1, l))),
            I8::from_array(levels.map(|l| offset[l as usize & 31] as i32)),
        )
    };
    let fx = u * w.to_f32() - 0.5;
    let fy = v * h.to_f32() - 0.5;
    let (x0, y0) = (floor_i(fx), floor_i(fy));
    let one = I8::splat(1);
    let xa = wrap_index(x0, w, s.wrap_u);
    let xb = wrap_index(x0 + one, w, s.wrap_u);
    let ra = wrap_index(y0, h, s.wrap_v) * w + first;
    let rb = wrap_index(y0 + one, h, s.wrap_v) * w + first;
    Footprint {
        level: levels,
        idx: [
            (ra + xa).to_array(),
            (ra + xb).to_array(),
            (rb + xa).to_array(),
            (rb + xb).to_array(),
        ],
        tx: (fx - x0.to_f32()).to_array(),
        ty: (fy - y0.to_f32()).to_array(),
    }
}

#[cfg(test)]
mod tests;
