//! The number types the lighting model is written over, behind one trait ([`Num`]):
//!
//! - `f32`: the renderer's vertex stage and pixel probe;
//! - `f64`: the references in [`crate::quality`];
//! - [`F8`]: eight f32 lanes, what the pixel stages run (compiled once per kernel).
//!
//! Code over [`Num`] is written the way lane code must be: a comparison gives a mask
//! ([`Num::M`], `bool` for scalars, [`M8`] for lanes), a decision is a [`Num::select`], and
//! an early exit asks whether [`Num::any`] lane needs the work. For `f32` and `f64` these
//! compile to the plain `if` they replace. [`Real`] adds what only a scalar has (ordering,
//! conversion to `f64`), for code that is never run on lanes.

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use glam::{DVec3, Vec3};

use super::lanes::{F8, M8, V3};
use super::level::Level;

/// A float type (scalar or lanes) with a matching 3-vector and mask.
pub trait Num:
    Copy
    + std::fmt::Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Send
    + Sync
    + 'static
{
    /// The 3-vector of this type (`Vec3`, `DVec3` or [`V3`]).
    type V: Copy
        + std::fmt::Debug
        + Send
        + Sync
        + Add<Output = Self::V>
        + Sub<Output = Self::V>
        + Mul<Output = Self::V>
        + Mul<Self, Output = Self::V>
        + Neg<Output = Self::V>;
    /// The result of a comparison (`bool`, or [`M8`] for lanes).
    type M: Copy
        + std::fmt::Debug
        + BitAnd<Output = Self::M>
        + BitOr<Output = Self::M>
        + Not<Output = Self::M>;

    const ZERO: Self;
    const ONE: Self;

    fn of(x: f32) -> Self;
    fn of64(x: f64) -> Self;
    fn vec(v: Vec3) -> Self::V;
    fn splat(x: Self) -> Self::V;
    fn dot(a: Self::V, b: Self::V) -> Self;
    fn cross(a: Self::V, b: Self::V) -> Self::V;
    fn new3(x: Self, y: Self, z: Self) -> Self::V;
    /// The components of `v`.
    fn xyz(v: Self::V) -> [Self; 3];
    fn normalize_or_zero(a: Self::V) -> Self::V;
    fn sqrt(self) -> Self;
    /// `self^e` for `self > 0`; the value for `self <= 0` is unspecified (select it away).
    fn powf(self, e: Self) -> Self;
    /// `self^n` for a whole `n` and `self > 0` (for `self <= 0` unspecified: select it
    /// away), by repeated squaring with every factor clamped at 2^-60, in every type: the
    /// steps of [`F8::powi`], so scalar f32 (the vertex stage) and lanes agree bit for bit.
    fn powi(self, n: u32) -> Self;
    /// `e^self` (lanes: [`F8::exp`], relative error below 3e-7 + 1.2e-7 |self|).
    fn exp(self) -> Self;
    /// `cos self` in radians (lanes: [`F8::cos`], absolute error below 2e-7 for |self| up to
    /// 8000).
    fn cos(self) -> Self;
    fn gt(self, o: Self) -> Self::M;
    fn ge(self, o: Self) -> Self::M;
    /// Where the value is finite.
    fn finite(self) -> Self::M;
    /// `a` where `m` holds, else `b`.
    fn select(m: Self::M, a: Self, b: Self) -> Self;
    /// Whether `m` holds anywhere (in any lane).
    fn any(m: Self::M) -> bool;
    /// `a * b + c`, never fused (so results do not depend on the kernel or the build's
    /// target features).
    #[inline(always)]
    fn mul_add(a: Self, b: Self, c: Self) -> Self {
        a * b + c
    }

    /// `1 / self`.
    #[inline(always)]
    fn recip(self) -> Self {
        Self::ONE / self
    }

    #[inline(always)]
    fn lt(self, o: Self) -> Self::M {
        o.gt(self)
    }

    #[inline(always)]
    fn le(self, o: Self) -> Self::M {
        o.ge(self)
    }

    /// `a` where `m` holds, else `b`, per component.
    #[inline(always)]
    fn vselect(m: Self::M, a: Self::V, b: Self::V) -> Self::V {
        let (a, b) = (Self::xyz(a), Self::xyz(b));
        Self::new3(
            Self::select(m, a[0], b[0]),
            Self::select(m, a[1], b[1]),
            Self::select(m, a[2], b[2]),
        )
    }

    /// The larger of the two; `NaN` in `self` gives `o`.
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        Self::select(self.gt(o), self, o)
    }

    /// The smaller of the two; `NaN` in `self` gives `o`.
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        Self::select(o.gt(self), self, o)
    }

    /// Clamped to [0, 1]; `NaN` gives 0.
    #[inline(always)]
    fn clamp01(self) -> Self {
        self.max(Self::ZERO).min(Self::ONE)
    }

    #[inline(always)]
    fn length(a: Self::V) -> Self {
        Self::dot(a, a).sqrt()
    }

    /// The largest component.
    #[inline(always)]
    fn vmax(a: Self::V) -> Self {
        let [x, y, z] = Self::xyz(a);
        x.max(y).max(z)
    }
}

/// A scalar [`Num`]: ordered, convertible to `f64`.
pub trait Real: Num<M = bool> + PartialOrd {
    fn to_f64(self) -> f64;
    fn to_vec3(v: Self::V) -> Vec3;
    #[inline(always)]
    fn is_finite(self) -> bool {
        self.finite()
    }
}

// powf, exp and cos are the `libm` crate's (the same bits on every machine), not std's (the
// platform's libm).
macro_rules! real {
    ($t:ty, $v:ty, $from:expr, $to:expr, $powf:path, $exp:path, $cos:path) => {
        impl Num for $t {
            type V = $v;
            type M = bool;
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            #[inline(always)]
            fn of(x: f32) -> Self {
                x as $t
            }
            #[inline(always)]
            fn of64(x: f64) -> Self {
                x as $t
            }
            #[inline(always)]
            fn vec(v: Vec3) -> $v {
                $from(v)
            }
            #[inline(always)]
            fn splat(x: Self) -> $v {
                <$v>::splat(x)
            }
            #[inline(always)]
            fn dot(a: $v, b: $v) -> Self {
                a.dot(b)
            }
            #[inline(always)]
            fn cross(a: $v, b: $v) -> $v {
                a.cross(b)
            }
            #[inline(always)]
            fn new3(x: Self, y: Self, z: Self) -> $v {
                <$v>::new(x, y, z)
            }
            #[inline(always)]
            fn xyz(v: $v) -> [Self; 3] {
                v.to_array()
            }
            /// glam's `normalize_or_zero`, step for step, with the hardware square root:
            /// glam built with its `libm` feature takes libm's software one, which gives
            /// the same bits (a square root is correctly rounded) in about ten times the
            /// time, on every vertex.
            #[inline(always)]
            fn normalize_or_zero(a: $v) -> $v {
                let rcp = 1.0 / <$t>::sqrt(a.dot(a));
                if rcp.is_finite() && rcp > 0.0 {
                    a * rcp
                } else {
                    <$v>::ZERO
                }
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline(always)]
            fn powf(self, e: Self) -> Self {
                $powf(self, e)
            }
            #[inline(always)]
            fn powi(self, n: u32) -> Self {
                // The steps of `F8::powi`, one value at a time (so scalar f32 and lanes
                // agree bit for bit; f64 rounds 2^-29 times finer).
                let tiny = <$t>::from(super::lanes::TINY_FACTOR);
                let floor = |v: $t| if v > tiny { v } else { tiny };
                super::lanes::powi_by_squaring(self, n, floor, 1.0)
            }
            #[inline(always)]
            fn exp(self) -> Self {
                $exp(self)
            }
            #[inline(always)]
            fn cos(self) -> Self {
                $cos(self)
            }
            #[inline(always)]
            fn gt(self, o: Self) -> bool {
                self > o
            }
            #[inline(always)]
            fn ge(self, o: Self) -> bool {
                self >= o
            }
            #[inline(always)]
            fn finite(self) -> bool {
                <$t>::is_finite(self)
            }
            #[inline(always)]
            fn select(m: bool, a: Self, b: Self) -> Self {
                if m {
                    a
                } else {
                    b
                }
            }
            #[inline(always)]
            fn vselect(m: bool, a: $v, b: $v) -> $v {
                if m {
                    a
                } else {
                    b
                }
            }
            #[inline(always)]
            fn any(m: bool) -> bool {
                m
            }
            #[inline(always)]
            fn vmax(a: $v) -> Self {
                a.max_element()
            }
        }

        impl Real for $t {
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline(always)]
            fn to_vec3(v: $v) -> Vec3 {
                $to(v)
            }
        }
    };
}

real!(f32, Vec3, |v| v, |v| v, libm::powf, libm::expf, libm::cosf);
real!(
    f64,
    DVec3,
    |v: Vec3| v.as_dvec3(),
    |v: DVec3| v.as_vec3(),
    libm::pow,
    libm::exp,
    libm::cos
);

/// Eight f32 lanes of level `L`, what the pixel stages run: every kernel computes the same
/// bits (no fused multiply-add, see [`super::lanes`]); the level only decides the
/// instructions.
impl<L: Level> Num for F8<L> {
    type V = V3<L>;
    type M = M8<L>;
    const ZERO: Self = F8::<L>::ZERO;
    const ONE: Self = F8::<L>::ONE;
    #[inline(always)]
    fn of(x: f32) -> Self {
        F8::splat(x)
    }
    #[inline(always)]
    fn of64(x: f64) -> Self {
        F8::splat(x as f32)
    }
    #[inline(always)]
    fn vec(v: Vec3) -> V3<L> {
        V3::splat(v)
    }
    #[inline(always)]
    fn splat(x: Self) -> V3<L> {
        V3::new(x, x, x)
    }
    #[inline(always)]
    fn dot(a: V3<L>, b: V3<L>) -> Self {
        a.dot(b)
    }
    #[inline(always)]
    fn cross(a: V3<L>, b: V3<L>) -> V3<L> {
        a.cross(b)
    }
    #[inline(always)]
    fn new3(x: Self, y: Self, z: Self) -> V3<L> {
        V3::new(x, y, z)
    }
    #[inline(always)]
    fn xyz(v: V3<L>) -> [Self; 3] {
        [v.x, v.y, v.z]
    }
    #[inline(always)]
    fn normalize_or_zero(a: V3<L>) -> V3<L> {
        a.normalize_or_zero()
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        F8::sqrt(self)
    }
    #[inline(always)]
    fn powf(self, e: Self) -> Self {
        F8::powf(self, e)
    }
    #[inline(always)]
    fn powi(self, n: u32) -> Self {
        F8::powi(self, n)
    }
    #[inline(always)]
    fn exp(self) -> Self {
        F8::exp(self)
    }
    #[inline(always)]
    fn cos(self) -> Self {
        F8::cos(self)
    }
    #[inline(always)]
    fn gt(self, o: Self) -> M8<L> {
        F8::gt(self, o)
    }
    #[inline(always)]
    fn ge(self, o: Self) -> M8<L> {
        F8::ge(self, o)
    }
    #[inline(always)]
    fn finite(self) -> M8<L> {
        self.abs().lt(F8::splat(f32::INFINITY))
    }
    #[inline(always)]
    fn select(m: M8<L>, a: Self, b: Self) -> Self {
        F8::select(m, a, b)
    }
    #[inline(always)]
    fn any(m: M8<L>) -> bool {
        m.bits() != 0
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        F8::max(self, o)
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        F8::min(self, o)
    }
}
