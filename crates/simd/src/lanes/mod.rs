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

mod f8;
pub(crate) use f8::*;
mod v3;
pub use v3::*;
mod ints;

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

#[cfg(test)]
mod tests;
