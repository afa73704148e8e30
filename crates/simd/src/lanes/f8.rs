//! The arithmetic, comparisons and maths of [`F8`], eight f32 lanes.

use super::*;

impl<L: Level> F8<L> {
    pub const ZERO: Self = F8(L::F_ZERO, PhantomData);
    pub const ONE: Self = F8(L::F_ONE, PhantomData);
    /// 0, 1, ..., 7.
    pub const RAMP: Self = F8(L::F_RAMP, PhantomData);

    #[inline(always)]
    pub(super) fn new(v: L::F) -> Self {
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

    /// `e^self`, as `2^(self log2 e)` ([`F8::exp2`], so for lanes in about [-87, 88]; below
    /// gives ~1e-38, above ~inf): relative error below 3e-7 + 1.2e-7 |self| (the second term
    /// is the rounding of `log2 e` and of the product, amplified by the exponential).
    #[inline(always)]
    #[must_use]
    pub fn exp(self) -> Self {
        (self * Self::splat(std::f32::consts::LOG2_E)).exp2()
    }

    /// `cos` of lanes, for |self| up to 8000 (absolute error below 2e-7 there, 9.3e-8
    /// measured; larger arguments are untested). Cody and Waite's reduction by the
    /// nearest multiple `j` of π/2, in three parts (Cephes' `sinf`/`cosf` constants for π/4,
    /// doubled; `j` times the first two is exact for |j| < 8192), leaves `r` in [-π/4, π/4];
    /// Cephes' minimax polynomials give `cos r` and `sin r`, and the quadrant `j mod 4`
    /// picks `cos r`, `-sin r`, `-cos r` or `sin r`. No integer lanes: the quadrant is a
    /// whole float.
    #[inline(always)]
    #[must_use]
    #[allow(clippy::excessive_precision)] // the coefficients as published
    pub fn cos(self) -> Self {
        let j = (self * Self::splat(std::f32::consts::FRAC_2_PI) + Self::splat(0.5)).floor();
        let mut r = mad(j, Self::splat(-1.570_312_5), self);
        r = mad(j, Self::splat(-4.837_512_969_970_703_125e-4), r);
        r = mad(j, Self::splat(-7.549_789_954_891_882_16e-8), r);
        let quarter = Self::splat(0.25);
        let q = j - (j * quarter).floor() * Self::splat(4.0);
        let z = r * r;
        let mut c = Self::splat(2.443_315_711_809_948e-5);
        c = mad(c, z, Self::splat(-1.388_731_625_493_765e-3));
        c = mad(c, z, Self::splat(4.166_664_568_298_827e-2));
        c = mad(c * z, z, mad(Self::splat(-0.5), z, Self::ONE));
        let mut s = Self::splat(-1.951_529_589_1e-4);
        s = mad(s, z, Self::splat(8.332_160_873_6e-3));
        s = mad(s, z, Self::splat(-1.666_665_461_1e-1));
        s = mad(s * z, r, r);
        // Quadrants 1 and 3 take the sine, 1 and 2 the minus sign.
        let odd = (q - (q * Self::splat(0.5)).floor() * Self::splat(2.0)).gt(quarter);
        let v = Self::select(odd, s, c);
        let neg = (q - Self::splat(1.5)).abs().lt(Self::ONE);
        Self::select(neg, -v, v)
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
