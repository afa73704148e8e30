//! The integer lanes [`I8`]: arithmetic, shifts, comparisons and conversions.

use super::*;

impl<L: Level> I8<L> {
    #[inline(always)]
    pub(super) fn new(v: L::I) -> Self {
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
