//! Eight-lane values for the fill and the shaders, generic over the [`Level`] they are built
//! on: [`F8`] (eight f32), [`M8`] (a lane mask), [`I8`] (eight i32) and [`V3`] (a vector
//! of three [`F8`]), plus the few transcendental functions shading needs (`log2`, `exp2`,
//! `pow`, `acos`, `atan2`) as polynomials that work on all lanes at once; and [`Lane`], the
//! level-free form in which lanes are stored between functions (in batches, tiles, stage
//! registers).
//!
//! Code over lanes is written once, generic over `L: Level`, and compiled per kernel by
//! [`per_kernel!`](crate::per_kernel): every operation here is `#[inline(always)]` and one
//! or two vector instructions of the level (see [`crate::level`] for why not a loop left to
//! the vectorizer). No fused multiply-add, no approximate instruction: every kernel computes
//! the same bits (the tests render each golden on every kernel the machine has and compare
//! them bit for bit). An FMA kernel would be a little faster on arithmetic-bound stages and
//! give other images on other CPUs.

use std::marker::PhantomData;
use std::ops::{
    Add, AddAssign, BitAnd, BitOr, BitXor, Div, Mul, MulAssign, Neg, Not, Sub, SubAssign,
};

pub use crate::level::{Level, LANES};

/// Eight f32 lanes as stored between functions: the level-free form of [`F8`] (aligned, so
/// a level loads it as one register).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[repr(C, align(32))]
pub struct Lane(pub [f32; LANES]);

impl Lane {
    pub const ZERO: Lane = Lane([0.0; LANES]);
    pub const ONE: Lane = Lane([1.0; LANES]);

    #[inline(always)]
    #[must_use]
    pub fn splat(x: f32) -> Self {
        Lane([x; LANES])
    }

    /// The lanes as a value of level `L`.
    #[inline(always)]
    #[must_use]
    pub fn get<L: Level>(&self) -> F8<L> {
        F8::from_array(self.0)
    }

    /// Stores `v`.
    #[inline(always)]
    pub fn set<L: Level>(&mut self, v: F8<L>) {
        self.0 = v.to_array();
    }

    /// Stores `v` in the lanes of `m`, keeping the others (see [`F8::store_where`]).
    #[inline(always)]
    pub fn blend<L: Level>(&mut self, m: M8<L>, v: F8<L>) {
        v.store_where(m, &mut self.0);
    }
}

impl<L: Level> From<F8<L>> for Lane {
    #[inline(always)]
    fn from(v: F8<L>) -> Self {
        Lane(v.to_array())
    }
}

/// Eight f32 lanes of level `L`.
#[repr(transparent)]
pub struct F8<L: Level>(pub L::F, PhantomData<L>);

/// A mask of eight lanes of level `L`: all bits set (true) or clear (false) per lane.
#[repr(transparent)]
pub struct M8<L: Level>(pub L::I, PhantomData<L>);

/// Eight i32 lanes of level `L` (texel coordinates, levels, sizes); arithmetic wraps.
#[repr(transparent)]
pub struct I8<L: Level>(pub L::I, PhantomData<L>);

macro_rules! copy_debug {
    ($t:ident, $arr:ident) => {
        impl<L: Level> Clone for $t<L> {
            #[inline(always)]
            fn clone(&self) -> Self {
                *self
            }
        }
        impl<L: Level> Copy for $t<L> {}
        impl<L: Level> std::fmt::Debug for $t<L> {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, "{}{:?}", stringify!($t), self.$arr())
            }
        }
    };
}
copy_debug!(F8, to_array);
copy_debug!(M8, to_array);
copy_debug!(I8, to_array);

impl<L: Level> Default for F8<L> {
    #[inline(always)]
    fn default() -> Self {
        Self::ZERO
    }
}

impl<L: Level> Default for I8<L> {
    #[inline(always)]
    fn default() -> Self {
        I8(L::I_ZERO, PhantomData)
    }
}

/// `a * b + c`, rounded twice (never fused: see the module docs).
#[inline(always)]
#[must_use]
pub fn mad<L: Level>(a: F8<L>, b: F8<L>, c: F8<L>) -> F8<L> {
    a * b + c
}

impl<L: Level> F8<L> {
    pub const ZERO: Self = F8(L::F_ZERO, PhantomData);
    pub const ONE: Self = F8(L::F_ONE, PhantomData);
    /// 0, 1, ..., 7.
    pub const RAMP: Self = F8(L::F_RAMP, PhantomData);

    #[inline(always)]
    fn new(v: L::F) -> Self {
        F8(v, PhantomData)
    }

    #[inline(always)]
    #[must_use]
    pub fn splat(v: f32) -> Self {
        Self::new(L::splat(v))
    }

    #[inline(always)]
    #[must_use]
    pub fn from_array(a: [f32; LANES]) -> Self {
        Self::new(L::from_array(a))
    }

    #[inline(always)]
    #[must_use]
    pub fn to_array(self) -> [f32; LANES] {
        L::to_array(self.0)
    }

    /// Lane `i` (`i < 8`).
    #[inline(always)]
    #[must_use]
    pub fn lane(self, i: usize) -> f32 {
        self.to_array()[i]
    }

    /// The same value, kept in memory: a barrier that ends the compiler's view of how the
    /// value was computed (for code that must not be merged with what follows, such as a
    /// benchmark). Costs a store and a load.
    #[inline(always)]
    #[must_use]
    pub fn pin(self) -> Self {
        Self::from_array(std::hint::black_box(self.to_array()))
    }

    /// Eight consecutive values from `s` (which must hold at least eight).
    #[inline(always)]
    #[must_use]
    pub fn load(s: &[f32]) -> Self {
        let mut a = [0.0; LANES];
        a.copy_from_slice(&s[..LANES]);
        Self::from_array(a)
    }

    /// Writes the lanes to the first eight values of `s`.
    #[inline(always)]
    pub fn store(self, s: &mut [f32]) {
        s[..LANES].copy_from_slice(&self.to_array());
    }

    /// Writes the lanes of `m` to the first eight values of `s`, keeping the others: a
    /// load, a blend and a store. The destination reaches the store through
    /// `black_box`, so LLVM cannot fold the three into a masked store: on AMD CPUs AVX2's
    /// `vmaskmovps` store is microcoded and measured at about 40% of the fill's time where
    /// a blend and a plain store cost a few cycles.
    #[inline(always)]
    pub fn store_where(self, m: M8<L>, s: &mut [f32]) {
        let old = Self::load(s);
        let dst = std::hint::black_box(&mut s[..LANES]);
        Self::select(m, self, old).store(dst);
    }

    /// `f` applied to each lane (scalar code: for what has no lane form).
    #[inline(always)]
    #[must_use]
    pub fn map(self, f: impl Fn(f32) -> f32) -> Self {
        Self::from_array(self.to_array().map(f))
    }

    #[inline(always)]
    #[must_use]
    pub fn sqrt(self) -> Self {
        Self::new(L::sqrt(self.0))
    }

    /// `1 / self` (a division, not an approximate reciprocal).
    #[inline(always)]
    #[must_use]
    pub fn recip(self) -> Self {
        Self::ONE / self
    }

    #[inline(always)]
    #[must_use]
    pub fn abs(self) -> Self {
        let m = I8::<L>::splat(i32::MAX);
        Self::from_bits(self.bits() & m)
    }

    /// Lane-wise maximum; `NaN` in either gives `o`.
    #[inline(always)]
    #[must_use]
    pub fn max(self, o: Self) -> Self {
        Self::new(L::fmax(self.0, o.0))
    }

    /// Lane-wise minimum; `NaN` in either gives `o`.
    #[inline(always)]
    #[must_use]
    pub fn min(self, o: Self) -> Self {
        Self::new(L::fmin(self.0, o.0))
    }

    /// Clamped to `[lo, hi]`; `NaN` gives `lo`.
    #[inline(always)]
    #[must_use]
    pub fn clamp(self, lo: f32, hi: f32) -> Self {
        self.max(Self::splat(lo)).min(Self::splat(hi))
    }

    #[inline(always)]
    #[must_use]
    pub fn floor(self) -> Self {
        Self::new(L::floor(self.0))
    }

    #[inline(always)]
    #[must_use]
    pub fn gt(self, o: Self) -> M8<L> {
        M8::new(L::lt(o.0, self.0))
    }

    #[inline(always)]
    #[must_use]
    pub fn ge(self, o: Self) -> M8<L> {
        M8::new(L::le(o.0, self.0))
    }

    #[inline(always)]
    #[must_use]
    pub fn lt(self, o: Self) -> M8<L> {
        M8::new(L::lt(self.0, o.0))
    }

    #[inline(always)]
    #[must_use]
    pub fn le(self, o: Self) -> M8<L> {
        M8::new(L::le(self.0, o.0))
    }

    #[inline(always)]
    #[must_use]
    pub fn eq(self, o: Self) -> M8<L> {
        M8::new(L::eq(self.0, o.0))
    }

    /// Lanes of `a` where `m` is set, else of `b`.
    #[inline(always)]
    #[must_use]
    pub fn select(m: M8<L>, a: Self, b: Self) -> Self {
        Self::new(L::select(m.0, a.0, b.0))
    }

    /// The lanes' bits as integers.
    #[inline(always)]
    #[must_use]
    pub fn bits(self) -> I8<L> {
        I8::new(L::bits(self.0))
    }

    /// Floats with the bits of `i`.
    #[inline(always)]
    #[must_use]
    pub fn from_bits(i: I8<L>) -> Self {
        Self::new(L::from_bits(i.0))
    }

    /// Truncated toward zero; `i32::MIN` where it does not fit or is NaN.
    #[inline(always)]
    #[must_use]
    pub fn to_int(self) -> I8<L> {
        I8::new(L::to_int(self.0))
    }

    /// `base^e` for `base >= 0` (0 for `base <= 0`; `0^0` = 0), via [`F8::log2`] and
    /// [`F8::exp2`]: relative error below 2e-7 * (1 + |e log2 base|).
    #[inline(always)]
    #[must_use]
    pub fn powf(self, e: Self) -> Self {
        let p = (self.log2() * e).exp2();
        Self::select(self.gt(Self::ZERO), p, Self::ZERO)
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
        let tiny = Self::splat(TINY_FACTOR);
        powi_by_squaring(self, n, |v| v.max(tiny), Self::ONE)
    }

    /// `acos` of lanes in [-1, 1] (clamped there): Abramowitz & Stegun 4.4.46,
    /// `acos x = sqrt(1 - x) P(x)` on [0, 1] with a degree-7 `P` (error below 2e-8 in
    /// exact arithmetic; about 2e-7 in f32), and `acos(-x) = π - acos x`.
    #[inline(always)]
    #[must_use]
    #[allow(clippy::excessive_precision)] // the coefficients as published
    pub fn acos(self) -> Self {
        let x = self.clamp(-1.0, 1.0);
        let a = x.abs();
        let mut p = Self::splat(-0.001_262_491_1);
        for c in [
            0.006_670_090_1,
            -0.017_088_125_6,
            0.030_891_881_0,
            -0.050_174_304_6,
            0.088_978_987_4,
            -0.214_598_801_6,
            1.570_796_305_0,
        ] {
            p = mad(p, a, Self::splat(c));
        }
        let r = (Self::ONE - a).sqrt() * p;
        Self::select(x.lt(Self::ZERO), Self::splat(std::f32::consts::PI) - r, r)
    }

    /// `atan2(self, x)` (self is y), in (-π, π]; 0 where both are 0. The octant is reduced
    /// to `t = min/max` in [0, 1], `atan t` by a degree-11 odd minimax polynomial (error
    /// about 1e-5 rad), then reflected back.
    #[inline(always)]
    #[must_use]
    #[allow(clippy::excessive_precision)] // the coefficients as published
    pub fn atan2(self, x: Self) -> Self {
        let (ax, ay) = (x.abs(), self.abs());
        let hi = ax.max(ay);
        let lo = ax.min(ay);
        let t = Self::select(hi.gt(Self::ZERO), lo / hi, Self::ZERO);
        let t2 = t * t;
        let mut p = Self::splat(-0.011_721_20);
        for c in [
            0.052_653_32,
            -0.116_432_87,
            0.193_543_46,
            -0.332_623_47,
            0.999_977_26,
        ] {
            p = mad(p, t2, Self::splat(c));
        }
        let mut r = p * t;
        r = Self::select(ay.gt(ax), Self::splat(std::f32::consts::FRAC_PI_2) - r, r);
        r = Self::select(x.lt(Self::ZERO), Self::splat(std::f32::consts::PI) - r, r);
        Self::select(self.lt(Self::ZERO), -r, r)
    }

    /// Base-2 logarithm of positive finite lanes (others: unspecified but finite-safe).
    /// `x = m 2^k` with `m` in [sqrt(1/2), sqrt(2)), `log2 m = 2 atanh(s) / ln 2` with
    /// `s = (m - 1) / (m + 1)`, |s| < 0.1716, summed to s^9 (truncation below 1e-9).
    #[inline(always)]
    #[must_use]
    pub fn log2(self) -> Self {
        let bits = self.bits();
        // Exponent relative to the mantissa range [sqrt(1/2), sqrt(2)): offset by the bits
        // of sqrt(1/2) so the split happens there.
        let e = (bits - I8::splat(0x3f35_04f3)).sra::<23>();
        let k = e.to_f32();
        let m = Self::from_bits(bits - e.shl::<23>());
        let s = (m - Self::ONE) / (m + Self::ONE);
        let s2 = s * s;
        let mut p = Self::splat(1.0 / 9.0);
        p = mad(p, s2, Self::splat(1.0 / 7.0));
        p = mad(p, s2, Self::splat(1.0 / 5.0));
        p = mad(p, s2, Self::splat(1.0 / 3.0));
        p = mad(p, s2, Self::ONE);
        // 2 / ln 2
        mad(s * p, Self::splat(std::f32::consts::LOG2_E * 2.0), k)
    }

    /// `2^self`, for lanes in about [-126, 127] (clamped there: below gives ~0, above ~inf).
    /// Split into integer and fraction in [-0.5, 0.5], the fraction by a degree-6
    /// polynomial (relative error below 2e-7).
    #[inline(always)]
    #[must_use]
    pub fn exp2(self) -> Self {
        let x = self.clamp(-126.0, 127.0);
        let n = (x + Self::splat(0.5)).floor();
        let f = x - n;
        // Taylor coefficients of 2^f = e^(f ln 2).
        const L2: f32 = std::f32::consts::LN_2;
        let mut p = Self::splat(L2 * L2 * L2 * L2 * L2 * L2 / 720.0);
        p = mad(p, f, Self::splat(L2 * L2 * L2 * L2 * L2 / 120.0));
        p = mad(p, f, Self::splat(L2 * L2 * L2 * L2 / 24.0));
        p = mad(p, f, Self::splat(L2 * L2 * L2 / 6.0));
        p = mad(p, f, Self::splat(L2 * L2 / 2.0));
        p = mad(p, f, Self::splat(L2));
        p = mad(p, f, Self::ONE);
        // 2^n from the exponent bits: n + 127 is an integer in [1, 254], which adding 2^23
        // places in the low mantissa bits; shifting those to the exponent field (the rest
        // shifts out) builds the float 2^n without a float-to-int conversion.
        let biased = n + Self::splat(127.0 + 8_388_608.0);
        p * Self::from_bits(biased.bits().shl::<23>())
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

impl<L: Level> M8<L> {
    pub const NONE: Self = M8(L::I_ZERO, PhantomData);

    #[inline(always)]
    fn new(v: L::I) -> Self {
        M8(v, PhantomData)
    }

    /// Every lane set.
    #[inline(always)]
    #[must_use]
    pub fn all() -> Self {
        Self::new(L::isplat(-1))
    }

    /// The mask of the lanes whose bits are set in `bits` (bit i = lane i).
    #[inline(always)]
    #[must_use]
    pub fn from_bits(bits: u32) -> Self {
        Self::new(L::mask_of(bits))
    }

    /// Bit i set for each set lane i.
    #[inline(always)]
    #[must_use]
    pub fn bits(self) -> u32 {
        L::movemask(self.0)
    }

    /// Each lane as 0 or -1.
    #[inline(always)]
    #[must_use]
    pub fn to_array(self) -> [i32; LANES] {
        L::ito_array(self.0)
    }
}

impl<L: Level> BitAnd for M8<L> {
    type Output = Self;
    #[inline(always)]
    fn bitand(self, o: Self) -> Self {
        Self::new(L::and(self.0, o.0))
    }
}

impl<L: Level> BitOr for M8<L> {
    type Output = Self;
    #[inline(always)]
    fn bitor(self, o: Self) -> Self {
        Self::new(L::or(self.0, o.0))
    }
}

impl<L: Level> Not for M8<L> {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        Self::new(L::xor(self.0, L::isplat(-1)))
    }
}

macro_rules! binop {
    ($tr:ident, $f:ident, $lf:ident, $tra:ident, $fa:ident) => {
        impl<L: Level> $tr for F8<L> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                Self::new(L::$lf(self.0, o.0))
            }
        }
        impl<L: Level> $tr<f32> for F8<L> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: f32) -> Self {
                Self::new(L::$lf(self.0, L::splat(o)))
            }
        }
        impl<L: Level> $tra for F8<L> {
            #[inline(always)]
            fn $fa(&mut self, o: Self) {
                *self = Self::new(L::$lf(self.0, o.0));
            }
        }
    };
}
binop!(Add, add, add, AddAssign, add_assign);
binop!(Sub, sub, sub, SubAssign, sub_assign);
binop!(Mul, mul, mul, MulAssign, mul_assign);

impl<L: Level> Div for F8<L> {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        Self::new(L::div(self.0, o.0))
    }
}

impl<L: Level> Div<f32> for F8<L> {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: f32) -> Self {
        Self::new(L::div(self.0, L::splat(o)))
    }
}

impl<L: Level> Neg for F8<L> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self::from_bits(self.bits() ^ I8::splat(i32::MIN))
    }
}

/// Three [`F8`]: one 3-vector per lane.
pub struct V3<L: Level> {
    pub x: F8<L>,
    pub y: F8<L>,
    pub z: F8<L>,
}

impl<L: Level> Clone for V3<L> {
    #[inline(always)]
    fn clone(&self) -> Self {
        *self
    }
}

impl<L: Level> Copy for V3<L> {}

impl<L: Level> std::fmt::Debug for V3<L> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("V3")
            .field("x", &self.x)
            .field("y", &self.y)
            .field("z", &self.z)
            .finish()
    }
}

impl<L: Level> Default for V3<L> {
    #[inline(always)]
    fn default() -> Self {
        Self::new(F8::ZERO, F8::ZERO, F8::ZERO)
    }
}

impl<L: Level> V3<L> {
    #[inline(always)]
    #[must_use]
    pub fn new(x: F8<L>, y: F8<L>, z: F8<L>) -> Self {
        Self { x, y, z }
    }

    /// The same vector in every lane.
    #[inline(always)]
    #[must_use]
    pub fn splat(v: glam::Vec3) -> Self {
        Self::new(F8::splat(v.x), F8::splat(v.y), F8::splat(v.z))
    }

    /// The vector of three stored lanes.
    #[inline(always)]
    #[must_use]
    pub fn get(v: &[Lane; 3]) -> Self {
        Self::new(v[0].get(), v[1].get(), v[2].get())
    }

    /// Stores the vector into three lanes.
    #[inline(always)]
    pub fn set(self, v: &mut [Lane; 3]) {
        v[0].set(self.x);
        v[1].set(self.y);
        v[2].set(self.z);
    }

    /// Lane `i` as a vector.
    #[inline(always)]
    #[must_use]
    pub fn lane(self, i: usize) -> glam::Vec3 {
        glam::Vec3::new(self.x.lane(i), self.y.lane(i), self.z.lane(i))
    }

    #[inline(always)]
    #[must_use]
    pub fn dot(self, o: Self) -> F8<L> {
        mad(self.x, o.x, mad(self.y, o.y, self.z * o.z))
    }

    #[inline(always)]
    #[must_use]
    pub fn scale(self, s: F8<L>) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }

    /// The cross product `self × o`.
    #[inline(always)]
    #[must_use]
    pub fn cross(self, o: Self) -> Self {
        Self::new(
            mad(self.y, o.z, -(self.z * o.y)),
            mad(self.z, o.x, -(self.x * o.z)),
            mad(self.x, o.y, -(self.y * o.x)),
        )
    }

    /// Unit length, or zero where the length is zero or not finite.
    #[inline(always)]
    #[must_use]
    pub fn normalize_or_zero(self) -> Self {
        let len2 = self.dot(self);
        let inv = len2.sqrt().recip();
        let ok = len2.gt(F8::ZERO) & inv.lt(F8::splat(f32::INFINITY));
        self.scale(F8::select(ok, inv, F8::ZERO))
    }
}

/// Component-wise product with the same vector in every lane.
impl<L: Level> Mul<glam::Vec3> for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, c: glam::Vec3) -> Self {
        Self::new(self.x * c.x, self.y * c.y, self.z * c.z)
    }
}

/// Component-wise product.
impl<L: Level> Mul for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Self::new(self.x * o.x, self.y * o.y, self.z * o.z)
    }
}

/// A vector scaled per lane.
impl<L: Level> Mul<F8<L>> for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: F8<L>) -> Self {
        self.scale(s)
    }
}

impl<L: Level> Add for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl<L: Level> Sub for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl<L: Level> Neg for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}

impl<L: Level> I8<L> {
    #[inline(always)]
    fn new(v: L::I) -> Self {
        I8(v, PhantomData)
    }

    #[inline(always)]
    #[must_use]
    pub fn splat(v: i32) -> Self {
        Self::new(L::isplat(v))
    }

    #[inline(always)]
    #[must_use]
    pub fn from_array(a: [i32; LANES]) -> Self {
        Self::new(L::ifrom_array(a))
    }

    #[inline(always)]
    #[must_use]
    pub fn to_array(self) -> [i32; LANES] {
        L::ito_array(self.0)
    }

    /// Eight consecutive values from `s` (which must hold at least eight), as `i32` bits.
    #[inline(always)]
    #[must_use]
    pub fn load_u32(s: &[u32]) -> Self {
        let mut a = [0i32; LANES];
        for (d, v) in a.iter_mut().zip(&s[..LANES]) {
            *d = *v as i32;
        }
        Self::from_array(a)
    }

    /// Writes the lanes of `m` to the first eight values of `s` (as `u32` bits), keeping
    /// the others (see [`F8::store_where`]).
    #[inline(always)]
    pub fn store_where_u32(self, m: M8<L>, s: &mut [u32]) {
        let v = Self::select(m, self, Self::load_u32(s)).to_array();
        let dst = std::hint::black_box(&mut s[..LANES]);
        for (d, v) in dst.iter_mut().zip(v) {
            *d = v as u32;
        }
    }

    /// Shifted left by `N` bits.
    #[inline(always)]
    #[must_use]
    pub fn shl<const N: i32>(self) -> Self {
        Self::new(L::shl::<N>(self.0))
    }

    /// Shifted right by `N` bits, sign-filling.
    #[inline(always)]
    #[must_use]
    pub fn sra<const N: i32>(self) -> Self {
        Self::new(L::sra::<N>(self.0))
    }

    /// Shifted right by `N` bits, zero-filling.
    #[inline(always)]
    #[must_use]
    pub fn srl<const N: i32>(self) -> Self {
        Self::new(L::srl::<N>(self.0))
    }

    #[inline(always)]
    #[must_use]
    pub fn eq(self, o: Self) -> M8<L> {
        M8::new(L::ieq(self.0, o.0))
    }

    #[inline(always)]
    #[must_use]
    pub fn gt(self, o: Self) -> M8<L> {
        M8::new(L::igt(self.0, o.0))
    }

    #[inline(always)]
    #[must_use]
    pub fn lt(self, o: Self) -> M8<L> {
        M8::new(L::igt(o.0, self.0))
    }

    /// Lanes of `a` where `m` is set, else of `b`.
    #[inline(always)]
    #[must_use]
    pub fn select(m: M8<L>, a: Self, b: Self) -> Self {
        Self::new(L::iselect(m.0, a.0, b.0))
    }

    #[inline(always)]
    #[must_use]
    pub fn max(self, o: Self) -> Self {
        Self::select(self.gt(o), self, o)
    }

    #[inline(always)]
    #[must_use]
    pub fn min(self, o: Self) -> Self {
        Self::select(self.lt(o), self, o)
    }

    /// Clamped to `[0, hi]` (per lane).
    #[inline(always)]
    #[must_use]
    pub fn clamp0(self, hi: Self) -> Self {
        self.max(Self::splat(0)).min(hi)
    }

    /// Converted to floats (nearest, ties to even).
    #[inline(always)]
    #[must_use]
    pub fn to_f32(self) -> F8<L> {
        F8::new(L::to_float(self.0))
    }
}

macro_rules! ibinop {
    ($tr:ident, $f:ident, $lf:ident) => {
        impl<L: Level> $tr for I8<L> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                Self::new(L::$lf(self.0, o.0))
            }
        }
    };
}
ibinop!(Add, add, iadd);
ibinop!(Sub, sub, isub);
ibinop!(Mul, mul, imul);
ibinop!(BitAnd, bitand, and);
ibinop!(BitOr, bitor, or);
ibinop!(BitXor, bitxor, xor);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::level::Portable;
    use crate::KernelKind;

    type P = F8<Portable>;

    #[test]
    fn powi_matches_f64_within_n_roundings() {
        let tiny = 2f64.powi(-60);
        for n in 0..=128u32 {
            for i in 0..=4000 {
                let x = i as f32 / 4000.0;
                let got = f64::from(P::splat(x).powi(n).lane(3));
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
                let lane = P::splat(x).powi(n).lane(5);
                assert_eq!(crate::Num::powi(x, n).to_bits(), lane.to_bits(), "{x}^{n}");
            }
        }
        // Above 1 (N·H rounded up) and the exponent's bits one by one.
        for n in [1u32, 2, 3, 5, 7, 31, 32, 33, 64, 127, 128] {
            let x = 1.000_001f32;
            let got = f64::from(P::splat(x).powi(n).lane(0));
            let want = f64::from(x).powi(n as i32);
            assert!((got - want).abs() / want < 2e-5, "{x}^{n}: {got} vs {want}");
        }
    }

    fn check_pow() {
        let mut worst: f64 = 0.0;
        for i in 1..2000 {
            let x = i as f32 / 2000.0;
            for e in [1.0f32, 2.5, 8.0, 32.0, 128.0, 1000.0] {
                let got = P::splat(x).powf(P::splat(e)).lane(0);
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
        assert_eq!(P::splat(0.0).powf(P::splat(3.0)).lane(0), 0.0);
        assert_eq!(P::splat(-1.0).powf(P::splat(3.0)).lane(0), 0.0);
        assert_eq!(P::splat(1.0).powf(P::splat(500.0)).lane(0), 1.0);
        assert!(worst > 0.0);
    }

    #[test]
    fn acos_and_atan2_match_f64() {
        let (mut worst_acos, mut worst_atan) = (0.0f64, 0.0f64);
        for k in 0..=4000 {
            let x = -1.0 + 2.0 * k as f32 / 4000.0;
            let a = P::splat(x).acos().lane(0);
            worst_acos = worst_acos.max((f64::from(a) - f64::from(x).acos()).abs());
        }
        for k in 0..720 {
            let phi = (k as f64 + 0.25).to_radians() * 0.5 - std::f64::consts::PI;
            for r in [1e-3f64, 0.5, 1.0, 300.0] {
                let (y, x) = ((phi.sin() * r) as f32, (phi.cos() * r) as f32);
                let a = P::splat(y).atan2(P::splat(x)).lane(0);
                let want = f64::from(y).atan2(f64::from(x));
                worst_atan = worst_atan.max((f64::from(a) - want).abs());
            }
        }
        let zero = P::ZERO.atan2(P::ZERO).lane(0);
        assert_eq!(zero, 0.0);
        assert!(worst_acos < 1e-6, "acos {worst_acos:e}");
        assert!(worst_atan < 2e-5, "atan2 {worst_atan:e}");
    }

    #[test]
    fn pow_matches_f64() {
        check_pow();
    }

    #[test]
    fn log2_and_exp2_over_wide_ranges() {
        for k in -120..120 {
            for m in [1.0f32, 1.1, 1.41, 1.42, 1.9] {
                let x = m * 2f32.powi(k);
                let got = P::splat(x).log2().lane(0);
                let want = f64::from(x).log2();
                assert!(
                    (f64::from(got) - want).abs() < 2e-6 * want.abs().max(1.0),
                    "{x}"
                );
            }
        }
        for i in -1200..1200 {
            let x = i as f32 / 10.0;
            let got = f64::from(P::splat(x).exp2().lane(0));
            let want = 2f64.powf(f64::from(x));
            assert!(((got - want) / want).abs() < 3e-7, "{x}: {got} {want}");
        }
    }

    #[test]
    fn masks_and_selects() {
        let a = P::RAMP;
        let m = a.gt(P::splat(3.5));
        assert_eq!(m.bits(), 0b1111_0000);
        assert_eq!(M8::<Portable>::from_bits(0b1010).bits(), 0b1010);
        let s = P::select(m, a, -a);
        assert_eq!(s.to_array(), [0.0, -1.0, -2.0, -3.0, 4.0, 5.0, 6.0, 7.0]);
        assert_eq!((m & !m).bits(), 0);
        assert_eq!((m | !m).bits(), 0xff);
        let mut n = [f32::NAN; 8];
        n[1] = 2.0;
        assert_eq!(P::from_array(n).clamp(0.0, 1.0).to_array()[..2], [0.0, 1.0]);
        let v = V3::<Portable>::new(P::splat(3.0), P::splat(4.0), P::ZERO).normalize_or_zero();
        assert_eq!((v.x.lane(0), v.y.lane(0)), (0.6, 0.8));
        let z = V3::<Portable>::default().normalize_or_zero();
        assert_eq!(z.x.to_array(), [0.0; 8]);
    }

    /// Inputs for the kernel comparison: ordinary values, halves, large and tiny ones,
    /// signed zeros, infinities and NaN.
    fn awkward() -> Vec<Lane> {
        let special = [
            0.0f32,
            -0.0,
            0.5,
            -0.5,
            1.5,
            -1.5,
            2.5,
            -2.5,
            1e-30,
            -1e-30,
            8_388_607.5,
            -8_388_607.5,
            8_388_609.0,
            1e10,
            -1e10,
            3e9,
            -3e9,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            f32::MIN_POSITIVE,
            0.999_999_94,
            -0.999_999_94,
            123.456,
        ];
        let mut seed = 0x1234_5678u32;
        let mut out: Vec<Lane> = special
            .chunks(8)
            .map(|c| {
                let mut l = [0.0; 8];
                l[..c.len()].copy_from_slice(c);
                Lane(l)
            })
            .collect();
        for _ in 0..64 {
            let mut l = [0.0; 8];
            for x in &mut l {
                seed ^= seed << 13;
                seed ^= seed >> 17;
                seed ^= seed << 5;
                *x = f32::from_bits(seed % 0x7f00_0000) * if seed & 1 == 0 { 1.0 } else { -1.0 };
            }
            out.push(Lane(l));
        }
        out
    }

    crate::per_kernel! {
        /// Every primitive and function of the lanes applied to `a` and `b`, as bits.
        fn battery<L>(a: &[Lane], b: &[Lane], out: &mut Vec<u32>) {
            for (x, y) in a.iter().zip(b) {
                let (x, y) = (x.get::<L>(), y.get::<L>());
                let f = [
                    x + y,
                    x - y,
                    x * y,
                    x / y,
                    x.max(y),
                    x.min(y),
                    x.abs().sqrt(),
                    x.floor(),
                    x.to_int().to_f32(),
                    x.abs().log2(),
                    (x * 0.001).exp2(),
                    x.abs().powf(y.abs().min(F8::splat(40.0))),
                    x.abs().powi(7),
                    (x * 1e-9).acos(),
                    x.atan2(y),
                    -x,
                    F8::select(x.gt(y), x, y),
                    (x.bits() * I8::splat(31) + y.bits().sra::<3>()).to_f32(),
                ];
                for v in f {
                    out.extend(v.to_array().map(f32::to_bits));
                }
                let m = [x.gt(y), x.ge(y), x.lt(y), x.le(y), x.eq(y), x.bits().gt(y.bits())];
                out.extend(m.map(M8::bits));
                out.extend(x.to_int().to_array().map(|i| i as u32));
                let k = (x.bits().to_array()[0] as u32) & 0xff;
                out.push(M8::<L>::from_bits(k).bits());
            }
        }
    }

    /// Every kernel computes the same bits, edge cases included (the levels pin `max`,
    /// `min`, `floor` and the float-to-int conversion to one definition).
    #[test]
    fn every_kernel_computes_the_same_bits() {
        let a = awkward();
        let mut b = a.clone();
        b.rotate_left(3);
        let mut want = Vec::new();
        battery::pick(KernelKind::Portable)(&a, &b, &mut want);
        assert!(want.len() > 10_000);
        for k in KernelKind::available_kinds() {
            let mut got = Vec::new();
            battery::pick(k)(&a, &b, &mut got);
            assert_eq!(got, want, "{k:?}");
        }
        // The portable floor and conversion agree with Rust's scalar definitions.
        for l in &a {
            let v = l.get::<Portable>();
            for (i, x) in l.0.iter().enumerate() {
                let f = v.floor().lane(i);
                assert!(
                    f.to_bits() == x.floor().to_bits() || (f.is_nan() && x.is_nan()),
                    "floor {x}: {f}"
                );
                let t = v.to_int().to_array()[i];
                let want = if x.abs() < 2_147_483_648.0 {
                    *x as i32
                } else {
                    i32::MIN
                };
                assert_eq!(t, want, "trunc {x}");
            }
        }
    }
}
