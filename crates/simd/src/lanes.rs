//! Eight-lane values for the fill and the shaders: [`F8`] (eight f32), [`M8`] (a lane mask)
//! and [`V3`] (a vector of three [`F8`]), plus the few transcendental functions shading needs
//! (`log2`, `exp2`, `pow`) as polynomials that work on all lanes at once.
//!
//! Every operation is a loop over the eight lanes marked `#[inline(always)]`: compiled inside a
//! kernel entry point with AVX2 enabled (see [`super::kernel`]), LLVM turns each into one
//! 256-bit instruction; in the portable kernel the same source becomes two SSE2 instructions.
//! No `unsafe` and no intrinsics here: which instructions run is decided only by the target
//! features of the function these are inlined into.
//!
//! Fused multiply-add changes rounding, so it is not used implicitly: [`Kernel::fma`] is a
//! real FMA in kernels that have one and `a * b + c` in the portable kernel. Results of the
//! two kernels therefore differ by float rounding only (the tests state the tolerance).

// Lane loops index several arrays by the lane number on purpose: that shape vectorises.
#![allow(clippy::needless_range_loop)]

use std::ops::{Add, AddAssign, BitAnd, BitOr, Div, Mul, MulAssign, Neg, Not, Sub, SubAssign};

/// Lanes per block: one row of 8 pixels.
pub const LANES: usize = 8;

/// A kernel: the instruction set the fill and shaders are compiled for. Chosen once at run
/// time ([`super::KernelKind`]); generic code takes it as a type parameter so each kernel gets
/// its own copy of the inner loops.
pub trait Kernel: Copy + Default + Send + Sync + 'static {
    /// Whether [`Kernel::fma`] is fused.
    const FMA: bool;
    /// `a * b + c`, fused if the kernel has FMA.
    #[inline(always)]
    fn fma(a: F8, b: F8, c: F8) -> F8 {
        if Self::FMA {
            let mut r = [0.0; LANES];
            for i in 0..LANES {
                r[i] = a.0[i].mul_add(b.0[i], c.0[i]);
            }
            F8(r)
        } else {
            a * b + c
        }
    }
}

/// Eight f32 lanes.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[repr(C, align(32))]
pub struct F8(pub [f32; LANES]);

/// A mask of eight lanes: all bits set (true) or clear (false) per lane.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[repr(C, align(32))]
pub struct M8(pub [u32; LANES]);

macro_rules! lanewise {
    ($a:expr, $b:expr, $op:tt) => {{
        let mut r = [0.0; LANES];
        for i in 0..LANES {
            r[i] = $a.0[i] $op $b.0[i];
        }
        F8(r)
    }};
}

impl F8 {
    pub const ZERO: F8 = F8([0.0; LANES]);
    pub const ONE: F8 = F8([1.0; LANES]);
    /// 0, 1, ..., 7.
    pub const RAMP: F8 = F8([0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);

    #[inline(always)]
    #[must_use]
    pub fn splat(v: f32) -> Self {
        F8([v; LANES])
    }

    /// Eight consecutive values from `s` (which must hold at least eight).
    #[inline(always)]
    #[must_use]
    pub fn load(s: &[f32]) -> Self {
        let mut r = [0.0; LANES];
        r.copy_from_slice(&s[..LANES]);
        F8(r)
    }

    #[inline(always)]
    #[must_use]
    pub fn map(self, f: impl Fn(f32) -> f32) -> Self {
        let mut r = [0.0; LANES];
        for i in 0..LANES {
            r[i] = f(self.0[i]);
        }
        F8(r)
    }

    #[inline(always)]
    #[must_use]
    pub fn sqrt(self) -> Self {
        self.map(f32::sqrt)
    }

    /// `1 / self`.
    #[inline(always)]
    #[must_use]
    pub fn recip(self) -> Self {
        F8::ONE / self
    }

    #[inline(always)]
    #[must_use]
    pub fn abs(self) -> Self {
        self.map(f32::abs)
    }

    /// Lane-wise maximum; `NaN` in `self` gives `o`.
    #[inline(always)]
    #[must_use]
    pub fn max(self, o: Self) -> Self {
        let mut r = [0.0; LANES];
        for i in 0..LANES {
            r[i] = if self.0[i] > o.0[i] {
                self.0[i]
            } else {
                o.0[i]
            };
        }
        F8(r)
    }

    /// Lane-wise minimum; `NaN` in `self` gives `o`.
    #[inline(always)]
    #[must_use]
    pub fn min(self, o: Self) -> Self {
        let mut r = [0.0; LANES];
        for i in 0..LANES {
            r[i] = if self.0[i] < o.0[i] {
                self.0[i]
            } else {
                o.0[i]
            };
        }
        F8(r)
    }

    /// Clamped to `[lo, hi]`; `NaN` gives `lo`.
    #[inline(always)]
    #[must_use]
    pub fn clamp(self, lo: f32, hi: f32) -> Self {
        self.max(F8::splat(lo)).min(F8::splat(hi))
    }

    #[inline(always)]
    #[must_use]
    pub fn floor(self) -> Self {
        self.map(f32::floor)
    }

    #[inline(always)]
    #[must_use]
    pub fn gt(self, o: Self) -> M8 {
        cmp(self, o, |a, b| a > b)
    }

    #[inline(always)]
    #[must_use]
    pub fn ge(self, o: Self) -> M8 {
        cmp(self, o, |a, b| a >= b)
    }

    #[inline(always)]
    #[must_use]
    pub fn lt(self, o: Self) -> M8 {
        cmp(self, o, |a, b| a < b)
    }

    /// Lanes of `a` where `m` is set, else of `b`.
    #[inline(always)]
    #[must_use]
    pub fn select(m: M8, a: Self, b: Self) -> Self {
        // Bit operations, not `if`: the branchy form compiled to a scalar load per lane.
        let mut r = [0.0; LANES];
        for i in 0..LANES {
            r[i] = f32::from_bits((m.0[i] & a.0[i].to_bits()) | (!m.0[i] & b.0[i].to_bits()));
        }
        F8(r)
    }

    /// `base^e` for `base >= 0` (0 for `base <= 0`; `0^0` = 0), via [`F8::log2`] and
    /// [`F8::exp2`]: relative error below 2e-7 * (1 + |e log2 base|).
    #[inline(always)]
    #[must_use]
    pub fn powf<K: Kernel>(self, e: F8) -> Self {
        let p = (self.log2::<K>() * e).exp2::<K>();
        F8::select(self.gt(F8::ZERO), p, F8::ZERO)
    }

    /// `self^n` for a whole exponent `n` (1 for `n = 0`) by repeated squaring: `log2 n`
    /// squarings and at most as many products instead of [`F8::powf`]'s logarithm,
    /// division and exponential (a Phong or Blinn highlight with `n = 32`: 5 multiplies).
    /// Relative error below `(n - 1) * 1.2e-7` for `self` in (0, 1]: no more than the
    /// rounding of `self` to f32 already carries into `self^n` (n times its own). Every
    /// factor is clamped from below at 2^-60 so no product is subnormal (slow on some CPUs):
    /// a true value under 2^-60 comes out at most 2^-60, and 0 or less comes out 2^-60 too
    /// (callers select such lanes away, as for `powf`).
    #[inline(always)]
    #[must_use]
    pub fn powi(self, n: u32) -> Self {
        let tiny = F8::splat(TINY_FACTOR);
        powi_by_squaring(self, n, |v| v.max(tiny), F8::ONE)
    }

    /// `acos` of lanes in [-1, 1] (clamped there): Abramowitz & Stegun 4.4.46,
    /// `acos x = sqrt(1 - x) P(x)` on [0, 1] with a degree-7 `P` (error below 2e-8 in
    /// exact arithmetic; about 2e-7 in f32), and `acos(-x) = π - acos x`.
    #[inline(always)]
    #[must_use]
    #[allow(clippy::excessive_precision)] // the coefficients as published
    pub fn acos<K: Kernel>(self) -> Self {
        let x = self.clamp(-1.0, 1.0);
        let a = x.abs();
        let mut p = F8::splat(-0.001_262_491_1);
        for c in [
            0.006_670_090_1,
            -0.017_088_125_6,
            0.030_891_881_0,
            -0.050_174_304_6,
            0.088_978_987_4,
            -0.214_598_801_6,
            1.570_796_305_0,
        ] {
            p = K::fma(p, a, F8::splat(c));
        }
        let r = (F8::ONE - a).sqrt() * p;
        F8::select(x.lt(F8::ZERO), F8::splat(std::f32::consts::PI) - r, r)
    }

    /// `atan2(self, x)` (self is y), in (-π, π]; 0 where both are 0. The octant is reduced
    /// to `t = min/max` in [0, 1], `atan t` by a degree-11 odd minimax polynomial (error
    /// about 1e-5 rad), then reflected back.
    #[inline(always)]
    #[must_use]
    #[allow(clippy::excessive_precision)] // the coefficients as published
    pub fn atan2<K: Kernel>(self, x: F8) -> Self {
        let (ax, ay) = (x.abs(), self.abs());
        let hi = ax.max(ay);
        let lo = ax.min(ay);
        let t = F8::select(hi.gt(F8::ZERO), lo / hi, F8::ZERO);
        let t2 = t * t;
        let mut p = F8::splat(-0.011_721_20);
        for c in [
            0.052_653_32,
            -0.116_432_87,
            0.193_543_46,
            -0.332_623_47,
            0.999_977_26,
        ] {
            p = K::fma(p, t2, F8::splat(c));
        }
        let mut r = p * t;
        r = F8::select(ay.gt(ax), F8::splat(std::f32::consts::FRAC_PI_2) - r, r);
        r = F8::select(x.lt(F8::ZERO), F8::splat(std::f32::consts::PI) - r, r);
        F8::select(self.lt(F8::ZERO), -r, r)
    }

    /// Base-2 logarithm of positive finite lanes (others: unspecified but finite-safe).
    /// `x = m 2^k` with `m` in [sqrt(1/2), sqrt(2)), `log2 m = 2 atanh(s) / ln 2` with
    /// `s = (m - 1) / (m + 1)`, |s| < 0.1716, summed to s^9 (truncation below 1e-9).
    #[inline(always)]
    #[must_use]
    pub fn log2<K: Kernel>(self) -> Self {
        let mut m = [0.0; LANES];
        let mut k = [0.0; LANES];
        for i in 0..LANES {
            let bits = self.0[i].to_bits();
            // Exponent relative to the mantissa range [sqrt(1/2), sqrt(2)): offset by the
            // bits of sqrt(1/2) so the split happens there.
            let shifted = bits.wrapping_sub(0x3f35_04f3);
            let e = (shifted as i32) >> 23;
            k[i] = e as f32;
            m[i] = f32::from_bits(bits.wrapping_sub((e as u32) << 23));
        }
        let (m, k) = (F8(m), F8(k));
        let s = (m - F8::ONE) / (m + F8::ONE);
        let s2 = s * s;
        let mut p = F8::splat(1.0 / 9.0);
        p = K::fma(p, s2, F8::splat(1.0 / 7.0));
        p = K::fma(p, s2, F8::splat(1.0 / 5.0));
        p = K::fma(p, s2, F8::splat(1.0 / 3.0));
        p = K::fma(p, s2, F8::ONE);
        // 2 / ln 2
        K::fma(s * p, F8::splat(std::f32::consts::LOG2_E * 2.0), k)
    }

    /// `2^self`, for lanes in about [-126, 127] (clamped there: below gives ~0, above ~inf).
    /// Split into integer and fraction in [-0.5, 0.5], the fraction by a degree-6
    /// polynomial (relative error below 2e-7).
    #[inline(always)]
    #[must_use]
    pub fn exp2<K: Kernel>(self) -> Self {
        let x = self.clamp(-126.0, 127.0);
        let n = (x + F8::splat(0.5)).floor();
        let f = x - n;
        // Taylor coefficients of 2^f = e^(f ln 2).
        const L: f32 = std::f32::consts::LN_2;
        let mut p = F8::splat(L * L * L * L * L * L / 720.0);
        p = K::fma(p, f, F8::splat(L * L * L * L * L / 120.0));
        p = K::fma(p, f, F8::splat(L * L * L * L / 24.0));
        p = K::fma(p, f, F8::splat(L * L * L / 6.0));
        p = K::fma(p, f, F8::splat(L * L / 2.0));
        p = K::fma(p, f, F8::splat(L));
        p = K::fma(p, f, F8::ONE);
        // 2^n from the exponent bits: n + 127 is an integer in [1, 254], which adding 2^23
        // places in the low mantissa bits; shifting those to the exponent field (the rest
        // shifts out) builds the float 2^n without a float-to-int conversion.
        let biased = n + F8::splat(127.0 + 8_388_608.0);
        let mut r = [0.0; LANES];
        for i in 0..LANES {
            let scale = f32::from_bits(biased.0[i].to_bits() << 23);
            r[i] = p.0[i] * scale;
        }
        F8(r)
    }
}

/// 2^-60 (biased exponent 67): the floor of every factor in [`powi_by_squaring`].
pub(crate) const TINY_FACTOR: f32 = f32::from_bits(67 << 23);

/// `x^n` by repeated squaring, every factor and product passed through `floor` (which
/// clamps it from below at [`TINY_FACTOR`]), `one` for `n = 0`: the steps of [`F8::powi`],
/// shared with the scalar `Num::powi` so lanes and scalars take the same roundings.
#[inline(always)]
pub(crate) fn powi_by_squaring<T: Copy + Mul<Output = T>>(
    x: T,
    n: u32,
    floor: impl Fn(T) -> T,
    one: T,
) -> T {
    let mut b = floor(x);
    let mut r: Option<T> = None;
    let mut n = n;
    while n != 0 {
        if n & 1 != 0 {
            r = Some(r.map_or(b, |r| floor(r * b)));
        }
        n >>= 1;
        if n != 0 {
            b = floor(b * b);
        }
    }
    r.unwrap_or(one)
}

#[inline(always)]
fn cmp(a: F8, b: F8, f: impl Fn(f32, f32) -> bool) -> M8 {
    let mut r = [0u32; LANES];
    for i in 0..LANES {
        r[i] = u32::from(f(a.0[i], b.0[i])).wrapping_neg();
    }
    M8(r)
}

impl M8 {
    pub const ALL: M8 = M8([u32::MAX; LANES]);
    pub const NONE: M8 = M8([0; LANES]);

    /// The mask of the lanes whose bits are set in `bits` (bit i = lane i).
    #[inline(always)]
    #[must_use]
    pub fn from_bits(bits: u32) -> Self {
        let mut r = [0u32; LANES];
        for (i, x) in r.iter_mut().enumerate() {
            *x = if bits >> i & 1 != 0 { u32::MAX } else { 0 };
        }
        M8(r)
    }

    /// Bit i set for each set lane i.
    #[inline(always)]
    #[must_use]
    pub fn bits(self) -> u32 {
        super::kernel::sign_bits(self.0)
    }
}

impl BitAnd for M8 {
    type Output = M8;
    #[inline(always)]
    fn bitand(self, o: M8) -> M8 {
        let mut r = [0u32; LANES];
        for i in 0..LANES {
            r[i] = self.0[i] & o.0[i];
        }
        M8(r)
    }
}

impl BitOr for M8 {
    type Output = M8;
    #[inline(always)]
    fn bitor(self, o: M8) -> M8 {
        let mut r = [0u32; LANES];
        for i in 0..LANES {
            r[i] = self.0[i] | o.0[i];
        }
        M8(r)
    }
}

impl Not for M8 {
    type Output = M8;
    #[inline(always)]
    fn not(self) -> M8 {
        let mut r = [0u32; LANES];
        for i in 0..LANES {
            r[i] = !self.0[i];
        }
        M8(r)
    }
}

macro_rules! binop {
    ($tr:ident, $f:ident, $op:tt, $tra:ident, $fa:ident) => {
        impl $tr for F8 {
            type Output = F8;
            #[inline(always)]
            fn $f(self, o: F8) -> F8 {
                lanewise!(self, o, $op)
            }
        }
        impl $tr<f32> for F8 {
            type Output = F8;
            #[inline(always)]
            fn $f(self, o: f32) -> F8 {
                lanewise!(self, F8::splat(o), $op)
            }
        }
        impl $tra for F8 {
            #[inline(always)]
            fn $fa(&mut self, o: F8) {
                *self = lanewise!(*self, o, $op);
            }
        }
    };
}
binop!(Add, add, +, AddAssign, add_assign);
binop!(Sub, sub, -, SubAssign, sub_assign);
binop!(Mul, mul, *, MulAssign, mul_assign);

impl Div for F8 {
    type Output = F8;
    #[inline(always)]
    fn div(self, o: F8) -> F8 {
        lanewise!(self, o, /)
    }
}

impl Neg for F8 {
    type Output = F8;
    #[inline(always)]
    fn neg(self) -> F8 {
        self.map(|x| -x)
    }
}

/// Three [`F8`]: one 3-vector per lane.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct V3 {
    pub x: F8,
    pub y: F8,
    pub z: F8,
}

impl V3 {
    #[inline(always)]
    #[must_use]
    pub fn new(x: F8, y: F8, z: F8) -> Self {
        Self { x, y, z }
    }

    /// The same vector in every lane.
    #[inline(always)]
    #[must_use]
    pub fn splat(v: glam::Vec3) -> Self {
        Self::new(F8::splat(v.x), F8::splat(v.y), F8::splat(v.z))
    }

    #[inline(always)]
    #[must_use]
    pub fn dot<K: Kernel>(self, o: V3) -> F8 {
        K::fma(self.x, o.x, K::fma(self.y, o.y, self.z * o.z))
    }

    #[inline(always)]
    #[must_use]
    pub fn scale(self, s: F8) -> V3 {
        V3::new(self.x * s, self.y * s, self.z * s)
    }

    /// The cross product `self × o`.
    #[inline(always)]
    #[must_use]
    pub fn cross<K: Kernel>(self, o: V3) -> V3 {
        V3::new(
            K::fma(self.y, o.z, -(self.z * o.y)),
            K::fma(self.z, o.x, -(self.x * o.z)),
            K::fma(self.x, o.y, -(self.y * o.x)),
        )
    }

    /// Unit length, or zero where the length is zero or not finite.
    #[inline(always)]
    #[must_use]
    pub fn normalize_or_zero<K: Kernel>(self) -> V3 {
        let len2 = self.dot::<K>(self);
        let inv = len2.sqrt().recip();
        let ok = len2.gt(F8::ZERO) & inv.lt(F8::splat(f32::INFINITY));
        self.scale(F8::select(ok, inv, F8::ZERO))
    }
}

/// Component-wise product with the same vector in every lane.
impl Mul<glam::Vec3> for V3 {
    type Output = V3;
    #[inline(always)]
    fn mul(self, c: glam::Vec3) -> V3 {
        V3::new(self.x * c.x, self.y * c.y, self.z * c.z)
    }
}

/// Component-wise product.
impl Mul for V3 {
    type Output = V3;
    #[inline(always)]
    fn mul(self, o: V3) -> V3 {
        V3::new(self.x * o.x, self.y * o.y, self.z * o.z)
    }
}

impl Add for V3 {
    type Output = V3;
    #[inline(always)]
    fn add(self, o: V3) -> V3 {
        V3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl Sub for V3 {
    type Output = V3;
    #[inline(always)]
    fn sub(self, o: V3) -> V3 {
        V3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl Neg for V3 {
    type Output = V3;
    #[inline(always)]
    fn neg(self) -> V3 {
        V3::new(-self.x, -self.y, -self.z)
    }
}

/// Eight i32 lanes (texel coordinates, levels, sizes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[repr(C, align(32))]
pub struct I8(pub [i32; LANES]);

impl I8 {
    #[inline(always)]
    #[must_use]
    pub fn splat(v: i32) -> Self {
        I8([v; LANES])
    }

    #[inline(always)]
    #[must_use]
    pub fn zip(self, o: Self, f: impl Fn(i32, i32) -> i32) -> Self {
        let mut r = [0; LANES];
        for i in 0..LANES {
            r[i] = f(self.0[i], o.0[i]);
        }
        I8(r)
    }

    #[inline(always)]
    #[must_use]
    pub fn wrapping_add(self, o: Self) -> Self {
        self.zip(o, i32::wrapping_add)
    }

    #[inline(always)]
    #[must_use]
    pub fn wrapping_mul(self, o: Self) -> Self {
        self.zip(o, i32::wrapping_mul)
    }

    /// Clamped to `[0, hi]` (per lane).
    #[inline(always)]
    #[must_use]
    pub fn clamp0(self, hi: Self) -> Self {
        self.zip(hi, |a, h| {
            let a = if a < 0 { 0 } else { a };
            if a > h {
                h
            } else {
                a
            }
        })
    }

    #[inline(always)]
    #[must_use]
    pub fn to_f32(self) -> F8 {
        let mut r = [0.0; LANES];
        for i in 0..LANES {
            r[i] = self.0[i] as f32;
        }
        F8(r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Clone, Copy, Default)]
    struct NoFma;
    impl Kernel for NoFma {
        const FMA: bool = false;
    }
    #[derive(Clone, Copy, Default)]
    struct Fused;
    impl Kernel for Fused {
        const FMA: bool = true;
    }

    #[test]
    fn powi_matches_f64_within_n_roundings() {
        let tiny = 2f64.powi(-60);
        for n in 0..=128u32 {
            for i in 0..=4000 {
                let x = i as f32 / 4000.0;
                let got = f64::from(F8::splat(x).powi(n).0[3]);
                let want = f64::from(x).powi(n as i32);
                if n == 0 {
                    assert_eq!(got, 1.0);
                } else if want < tiny {
                    assert!(got <= tiny * 1.000_001 && got > 0.0, "{x}^{n}: {got}");
                } else {
                    let rel = (got - want).abs() / want;
                    assert!(
                        rel <= f64::from(n - 1) * 1.2e-7 + 1e-9,
                        "{x}^{n}: {got} vs {want}"
                    );
                }
            }
        }
        // The scalar steps (`Num::powi` for f32) give the same bits.
        for n in [1u32, 2, 5, 32, 100, 128] {
            for i in 0..=1000 {
                let x = i as f32 / 1000.0;
                let lane = F8::splat(x).powi(n).0[5];
                assert_eq!(crate::Num::powi(x, n).to_bits(), lane.to_bits(), "{x}^{n}");
            }
        }
        // Above 1 (N·H rounded up) and the exponent's bits one by one.
        for n in [1u32, 2, 3, 5, 7, 31, 32, 33, 64, 127, 128] {
            let x = 1.000_001f32;
            let got = f64::from(F8::splat(x).powi(n).0[0]);
            let want = f64::from(x).powi(n as i32);
            assert!((got - want).abs() / want < 2e-5, "{x}^{n}: {got} vs {want}");
        }
    }

    fn check_pow<K: Kernel>() {
        let mut worst: f64 = 0.0;
        for i in 1..2000 {
            let x = i as f32 / 2000.0;
            for e in [1.0f32, 2.5, 8.0, 32.0, 128.0, 1000.0] {
                let got = F8::splat(x).powf::<K>(F8::splat(e)).0[0];
                let want = f64::from(x).powf(f64::from(e));
                if want < 1e-30 {
                    assert!(got < 1e-29, "{x}^{e} = {got}");
                    continue;
                }
                let rel = ((f64::from(got) - want) / want).abs();
                let bound = 4e-7 * (1.0 + (f64::from(e) * f64::from(x).log2()).abs());
                assert!(rel < bound, "{x}^{e}: {got} vs {want}, rel {rel}");
                worst = worst.max(rel / bound);
            }
        }
        assert_eq!(F8::splat(0.0).powf::<K>(F8::splat(3.0)).0[0], 0.0);
        assert_eq!(F8::splat(-1.0).powf::<K>(F8::splat(3.0)).0[0], 0.0);
        assert_eq!(F8::splat(1.0).powf::<K>(F8::splat(500.0)).0[0], 1.0);
        assert!(worst > 0.0);
    }

    #[test]
    fn acos_and_atan2_match_f64() {
        let (mut worst_acos, mut worst_atan) = (0.0f64, 0.0f64);
        for k in 0..=4000 {
            let x = -1.0 + 2.0 * k as f32 / 4000.0;
            let a = F8::splat(x).acos::<crate::kernel::Portable>().0[0];
            worst_acos = worst_acos.max((f64::from(a) - f64::from(x).acos()).abs());
        }
        for k in 0..720 {
            let phi = (k as f64 + 0.25).to_radians() * 0.5 - std::f64::consts::PI;
            for r in [1e-3f64, 0.5, 1.0, 300.0] {
                let (y, x) = ((phi.sin() * r) as f32, (phi.cos() * r) as f32);
                let a = F8::splat(y)
                    .atan2::<crate::kernel::Portable>(F8::splat(x))
                    .0[0];
                let want = f64::from(y).atan2(f64::from(x));
                worst_atan = worst_atan.max((f64::from(a) - want).abs());
            }
        }
        let zero = F8::ZERO.atan2::<crate::kernel::Portable>(F8::ZERO).0[0];
        assert_eq!(zero, 0.0);
        assert!(worst_acos < 1e-6, "acos {worst_acos:e}");
        assert!(worst_atan < 2e-5, "atan2 {worst_atan:e}");
    }

    #[test]
    fn pow_matches_f64_with_and_without_fma() {
        check_pow::<NoFma>();
        check_pow::<Fused>();
    }

    #[test]
    fn log2_and_exp2_over_wide_ranges() {
        for k in -120..120 {
            for m in [1.0f32, 1.1, 1.41, 1.42, 1.9] {
                let x = m * 2f32.powi(k);
                let got = F8::splat(x).log2::<NoFma>().0[0];
                let want = f64::from(x).log2();
                assert!(
                    (f64::from(got) - want).abs() < 2e-6 * want.abs().max(1.0),
                    "{x}"
                );
            }
        }
        for i in -1200..1200 {
            let x = i as f32 / 10.0;
            let got = f64::from(F8::splat(x).exp2::<Fused>().0[0]);
            let want = 2f64.powf(f64::from(x));
            assert!(((got - want) / want).abs() < 3e-7, "{x}: {got} {want}");
        }
    }

    #[test]
    fn masks_and_selects() {
        let a = F8::RAMP;
        let m = a.gt(F8::splat(3.5));
        assert_eq!(m.bits(), 0b1111_0000);
        assert_eq!(M8::from_bits(0b1010).bits(), 0b1010);
        let s = F8::select(m, a, -a);
        assert_eq!(s.0, [0.0, -1.0, -2.0, -3.0, 4.0, 5.0, 6.0, 7.0]);
        assert_eq!((m & !m).bits(), 0);
        assert_eq!((m | !m).bits(), 0xff);
        let mut n = F8::splat(f32::NAN);
        n.0[1] = 2.0;
        assert_eq!(n.clamp(0.0, 1.0).0[..2], [0.0, 1.0]);
        let v = V3::new(F8::splat(3.0), F8::splat(4.0), F8::ZERO).normalize_or_zero::<NoFma>();
        assert_eq!((v.x.0[0], v.y.0[0]), (0.6, 0.8));
        let z = V3::default().normalize_or_zero::<Fused>();
        assert_eq!(z, V3::default());
    }
}
